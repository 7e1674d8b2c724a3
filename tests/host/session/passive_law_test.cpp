// PassiveLaw (host/session/passive_law.hpp): what makes the law BoxHand sends passive. The
// closed loop against the emulated box is tests/integration/device/passive_rendering_test.cpp.
#include "session/passive_law.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace cathbox::session {
namespace {

tool::ForceLaw law_at(double force_mN, double insertion_mm = 100.0, double stiffness = 0.0) {
  tool::ForceLaw law;
  law.insertion0_mm = insertion_mm;
  law.force0_mN = force_mN;
  law.stiffness_mN_per_mm = stiffness;
  return law;
}

TEST(PassiveLaw, ForceStepsAreSlewLimitedFromTheLastLawsForce) {
  PassiveLaw p;  // 100 mN per 1 ms tick
  EXPECT_DOUBLE_EQ(p.shape(law_at(2000.0), {}).law.force0_mN, 100.0);
  EXPECT_DOUBLE_EQ(p.shape(law_at(2000.0), {}).law.force0_mN, 200.0);
  // A law with a spring: the next law's force is compared with this one's force, not with its
  // spring carried to the new position (the simulation's step says where the spring went).
  PassiveLaw q;
  for (int i = 0; i < 10; ++i) (void)q.shape(law_at(1000.0, 100.0, 50.0), {});
  EXPECT_DOUBLE_EQ(q.last().force0_mN, 1000.0);
  // 1 mm further in the simulation asks 3000: 1100 is sent.
  EXPECT_DOUBLE_EQ(q.shape(law_at(3000.0, 101.0, 50.0), {}).law.force0_mN, 1100.0);
}

// A stick anchor's spring (a valve or lumen holding the tool, 2 x 2e4 mN/mm) holds only until
// it slips at its friction limit a few um on, or not at all when the catheter round the tool
// moves with it (the coiling run's microwire and microcatheter advanced together at 20 mm/s):
// each step the simulation gives the force at the new place (here 0) with the same stiffness.
// Slewed from the spring carried 20 um on (800 mN a tick over the 100 mN step), the sent force
// climbed to the full scale while the tool's own force was 0. What the box renders stays the
// tool's force plus the sampled-stiffness damper, K T / 2 v = 20 mN s/mm x 20 mm/s = 400 mN, for
// a law that states the spring (Simulator::force_law no longer does while the catheter moves).
TEST(PassiveLaw, AStickSpringTheSimulationReanchorsDoesNotRatchetTheForce) {
  constexpr double kSpeed = 20.0;  // mm/s, 20 um a 1 ms tick
  PassiveLaw p;
  ShapedLaw s;
  double x = 100.0;
  double rendered = 0.0;  // + into the patient
  double sent_max_mN = 0.0;
  double rendered_max_mN = 0.0;  // resisting +
  for (int i = 0; i < 200; ++i) {
    x += kSpeed * 1e-3;
    s = p.shape(law_at(0.0, x, 40000.0), {rendered, kSpeed});
    rendered = s.output_mN(x, kSpeed);
    sent_max_mN = std::max(sent_max_mN, std::abs(s.law.force0_mN));
    rendered_max_mN = std::max(rendered_max_mN, -rendered);
  }
  EXPECT_DOUBLE_EQ(sent_max_mN, 0.0);
  EXPECT_NEAR(rendered_max_mN, 40000.0 * 1e-3 / 2.0 * kSpeed, 1e-6);
}

TEST(PassiveLaw, ForceStaysWithinFullScale) {
  PassiveLaw p;
  ShapedLaw s;
  // The box reports what it rendered (ShapedLaw::output_mN at the tool's place).
  for (int i = 0; i < 100; ++i) s = p.shape(law_at(9000.0), {s.output_mN(100.0, 0.0), 0.0});
  EXPECT_DOUBLE_EQ(s.law.force0_mN, 5000.0);
  EXPECT_DOUBLE_EQ(s.output_mN(100.0, 0.0), -5000.0);
  EXPECT_LE(s.out_max_mN, 5000.0);
  EXPECT_GE(s.out_min_mN, -5000.0);
  for (int i = 0; i < 200; ++i) s = p.shape(law_at(-9000.0), {s.output_mN(100.0, 0.0), 0.0});
  EXPECT_DOUBLE_EQ(s.law.force0_mN, -5000.0);
  EXPECT_DOUBLE_EQ(s.output_mN(100.0, 0.0), 5000.0);
}

// Colgate & Schenkel 1997: a spring K sampled with period T is passive with damping > K T / 2.
TEST(PassiveLaw, StiffnessMeetsTheSampledDataDampingBound) {
  PassiveLawLimits limits;
  limits.box_damping_mN_s_per_mm = 2.0;
  PassiveLaw p(limits);
  const ShapedLaw s = p.shape(law_at(0.0, 100.0, 20000.0), {});
  EXPECT_DOUBLE_EQ(s.law.damping_mN_s_per_mm, 20000.0 * 1e-3 / 2.0 - 2.0);
  EXPECT_DOUBLE_EQ(s.law.stiffness_mN_per_mm, 20000.0);
}

// Hannaford & Ryu 2002: energy the box delivered is taken out by damping at the next tick.
TEST(PassiveLaw, ObserverDissipatesWhatTheBoxDelivered) {
  PassiveLaw p;
  // The box pushed in with 1 N while the tool moved in at 10 mm/s for 1 ms: 10 uJ delivered.
  const ShapedLaw s = p.shape(law_at(0.0), {1000.0, 10.0});
  // alpha = E / (v^2 T) = 10 uJ / (100 mm^2/s^2 * 1 ms) = 100 mN s/mm, which takes it all.
  EXPECT_NEAR(s.law.damping_mN_s_per_mm, 100.0, 1e-9);
  EXPECT_NEAR(p.observed_energy_mJ(), 0.0, 1e-12);
  // Energy the box absorbed (resisting the motion) asks for nothing.
  PassiveLaw q;
  EXPECT_DOUBLE_EQ(q.shape(law_at(0.0), {-1000.0, 10.0}).law.damping_mN_s_per_mm, 0.0);
  EXPECT_LT(q.observed_energy_mJ(), 0.0);
}

TEST(PassiveLaw, ADroppedResistanceIsHeldAsADamper) {
  PassiveLaw p;
  ShapedLaw held;
  for (int i = 0; i < 30; ++i) held = p.shape(law_at(2000.0), {held.output_mN(100.0, 0.0), 0.0});
  // The wire buckles: the simulation's force falls to 0 in one tick, the tool going in.
  const ShapedLaw s = p.shape(law_at(0.0), {held.output_mN(100.0, 0.0), 5.0});
  EXPECT_DOUBLE_EQ(s.law.force0_mN, 1900.0);
  // The rest is a damper letting the tool go 10 mm/s faster, never resisting beyond ~2 N.
  EXPECT_GT(s.law.damping_mN_s_per_mm, 0.0);
  EXPECT_LT(s.law.damping_mN_s_per_mm, 2000.0 / 10.0);
  EXPECT_LE(s.out_min_mN, -1900.0);
  EXPECT_GE(s.out_min_mN, -2000.0);
  // Once the simulation's force has been let down, the damper fades.
  ShapedLaw later = s;
  for (int i = 0; i < 6000; ++i) later = p.shape(law_at(0.0), {later.output_mN(100.0, 5.0), 5.0});
  EXPECT_DOUBLE_EQ(later.law.force0_mN, 0.0);
  EXPECT_LT(later.law.damping_mN_s_per_mm, 0.01);
  // Going out (a wire relaxing after the hand let go), nothing holds it back.
  PassiveLaw q;
  for (int i = 0; i < 30; ++i) (void)q.shape(law_at(2000.0), {});
  EXPECT_DOUBLE_EQ(q.shape(law_at(0.0), {0.0, -5.0}).law.damping_mN_s_per_mm, 0.0);
}

// The box's slew limit holds for what it renders, not only for the law's force at its own place:
// the hand moving along a stiff law, and a damper's force gone when the hand stops, change the
// output by at most a step from what the box rendered last (its readback).
TEST(PassiveLaw, TheOutputMovesAtMostASlewStepFromWhatTheBoxRendered) {
  PassiveLaw p;
  ShapedLaw s;
  double x = 100.0;
  double rendered = 0.0;
  // A wire jammed at 2 N, 1,500 mN/mm at the clamp, the hand pushing at 30 mm/s.
  for (int i = 0; i < 40; ++i) {
    x += 0.03;
    s = p.shape(law_at(2000.0 + 1500.0 * (x - 100.0), x, 1500.0), {rendered, 30.0});
    const double out = s.output_mN(x + 0.03, 30.0);  // where the hand is when the box renders it
    EXPECT_LE(std::abs(out - rendered), 100.0 + 1e-9) << "tick " << i;
    rendered = out;
  }
  // The hand stops: the law's damping (K T / 2 at least) no longer resists.
  const ShapedLaw stopped = p.shape(law_at(2000.0 + 1500.0 * (x - 100.0), x, 1500.0), {rendered, 0.0});
  EXPECT_GE(s.law.damping_mN_s_per_mm, 1500.0 * 1e-3 / 2.0);
  EXPECT_LE(std::abs(stopped.output_mN(x, 0.0) - rendered), 100.0 + 1e-9);
}

}  // namespace
}  // namespace cathbox::session

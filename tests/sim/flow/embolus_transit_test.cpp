// A clot fragment in transit, in virtual time: its arrival against the analytic transit time
// (the path's lumen volume over its flow: L / v in a uniform tube), and where the flow model
// stops or turns it (flow arrest, reversed flow). And whether the flow breaks a free clot:
// Griffith's criterion with the toughness of Tutwiler et al. (Sci Adv 2020).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "flow/clot_fracture.hpp"
#include "flow/embolus.hpp"
#include "flow_test_support.hpp"

namespace cathbox::flow {
namespace {

using test::build_or_fail;
using test::link;
using test::load_model;
using test::straight;
using test::y_model;

constexpr double kTick_s = 1e-3;

// Parent 60 mm of r 1.5; on one side 40 mm of r 1.2 then a 40 mm taper 1.2 -> 0.6 (points
// every 2 mm), on the other 40 mm of r 0.8; 250 mL/min in, 180 / 70 mL/min out.
vessel::VesselModel y_with_taper() {
  vessel::VesselModel m = y_model(1.5, 1.2, 0.8, 24, 32);
  m.segments.push_back(straight(4, {0, 24, 92}, {0, 48, 124}, 1.2, 0.6));
  link(m, 2, 4);
  return m;
}

FlowSettings y_settings() {
  FlowSettings s;
  s.calibrate_terminals = false;
  s.outlets = {{4, 180.0, 1}, {3, 70.0, 2}};
  s.inflows = {{1, 250.0, 3}};
  return s;
}

// Advanced in 1 ms ticks, the fragment lodges at the tick where the analytic transit ends:
// sum over the path of (lumen volume / flow). A 1.6 mm fragment from 5 mm into the parent goes
// into the wider branch and lodges at the first centreline point of the taper narrower than
// itself (r 0.78 at 28 mm: the radius falls 0.03 mm every 2 mm point).
TEST(EmbolusTransit, ArrivesAfterTheAnalyticTransitTime) {
  const vessel::VesselModel m = y_with_taper();
  const auto net = build_or_fail(m, y_settings());
  ASSERT_TRUE(net);
  const double q_parent = std::abs(net->segments()[0].flow_mm3_s);
  const double q_branch = std::abs(net->segments()[1].flow_mm3_s);
  ASSERT_NEAR(std::abs(net->segments()[3].flow_mm3_s), q_branch, 1e-9 * q_branch);
  const double r_lodge = 1.2 - 0.6 * 28.0 / 40.0;
  const double analytic_s = std::numbers::pi * 1.5 * 1.5 * 55.0 / q_parent + std::numbers::pi * 1.2 * 1.2 * 40.0 / q_branch +
                            std::numbers::pi * 28.0 * (1.2 * 1.2 + 1.2 * r_lodge + r_lodge * r_lodge) / 3.0 / q_branch;
  auto t = EmbolusTransit::start(*net, Fragment{{0, 5.0, 0.0}, 1.6, 3.0, kReferenceComposition});
  ASSERT_TRUE(t) << t.error().message;
  int ticks = 0;
  while (!t->done() && ticks < 100000) {
    const TransitState now = t->advance(*net, kTick_s);
    EXPECT_EQ(now, t->done() ? TransitState::kLodged : TransitState::kTravelling);
    ++ticks;
  }
  ASSERT_EQ(t->state(), TransitState::kLodged);
  EXPECT_EQ(t->path().lodged.segment, 3u);
  EXPECT_NEAR(t->path().lodged.arc_start_mm + t->path().lodged.length_mm, 28.0, 1e-9);
  EXPECT_NEAR(t->travelled_mm(), 55.0 + 40.0 + 28.0, 1e-9);
  // Lodged during the tick holding the analytic arrival: within one tick (1 ms) of it, and its
  // own clock exact to rounding.
  EXPECT_NEAR(t->elapsed_s(), analytic_s, 1e-9 * analytic_s);
  EXPECT_GE(ticks * kTick_s, analytic_s);
  EXPECT_LT((ticks - 1) * kTick_s, analytic_s);
  // The parent alone: path length over mean velocity.
  const double v_parent = q_parent / (std::numbers::pi * 1.5 * 1.5);
  std::printf("transit %.2f ms (analytic %.2f ms; parent %.0f mm/s, branch %.0f mm/s), %d ticks\n", 1e3 * t->elapsed_s(),
              1e3 * analytic_s, v_parent, q_branch / (std::numbers::pi * 1.2 * 1.2), ticks);
  // The timeless path agrees.
  const auto path = carry_fragment(*net, Fragment{{0, 5.0, 0.0}, 1.6, 3.0, kReferenceComposition});
  ASSERT_TRUE(path);
  EXPECT_EQ(path->segments, t->path().segments);
  EXPECT_EQ(path->lodged.arc_start_mm, t->path().lodged.arc_start_mm);
}

// Flow arrest on the wider branch: no flow through it (the parent's all goes the other way), a
// fragment in it waits where it is; deflated, it goes on and lodges where it would have.
// Nothing special-cased: the transit reads the network's flows.
TEST(EmbolusTransit, StallsUnderFlowArrestAndGoesOnWhenItIsLifted) {
  const vessel::VesselModel m = y_with_taper();
  const auto net = build_or_fail(m, y_settings());
  ASSERT_TRUE(net);
  ASSERT_TRUE(net->occlude({}, std::vector<FlowArrest>{{1}}));
  auto t = EmbolusTransit::start(*net, Fragment{{1, 5.0, 0.0}, 1.6, 3.0, kReferenceComposition});
  ASSERT_TRUE(t);
  for (int k = 0; k < 1000; ++k) EXPECT_EQ(t->advance(*net, kTick_s), TransitState::kStalled);
  EXPECT_EQ(t->position().segment, 1u);
  EXPECT_NEAR(t->position().arc_mm, 5.0, 1e-12);
  ASSERT_TRUE(net->occlude({}));
  for (int k = 0; k < 1000 && !t->done(); ++k) t->advance(*net, kTick_s);
  EXPECT_EQ(t->state(), TransitState::kLodged);
  EXPECT_EQ(t->path().lodged.segment, 3u);
}

// The neuro case with a balloon guide inflated in the left ICA: the sealed ICA carries nothing
// (a fragment there stalls: it does not travel distally), while the circle of Willis now feeds
// the left carotid terminus backwards through the left A1 (its flow reversed): a fragment in the
// A1 travels back to the terminus, against the A1's direction, and on into the left M1 and MCA.
TEST(EmbolusTransit, UnderBalloonGuideArrestTheFlowModelDecidesWhereItGoes) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const auto ica = static_cast<std::uint32_t>(*model.index_of(20));
  const auto a1 = static_cast<std::uint32_t>(*model.index_of(25));
  const double a1_open = net->segments()[a1].flow_mm3_s;
  ASSERT_TRUE(net->occlude({}, std::vector<FlowArrest>{{ica}}));
  const double a1_arrested = net->segments()[a1].flow_mm3_s;
  std::printf("left A1 %.1f mL/min open, %.1f mL/min under the left ICA's arrest\n", 0.06 * a1_open, 0.06 * a1_arrested);
  auto in_ica = EmbolusTransit::start(*net, Fragment{{ica, 20.0, 0.0}, 1.0, 2.0, kReferenceComposition});
  ASSERT_TRUE(in_ica);
  EXPECT_EQ(in_ica->advance(*net, 1.0), TransitState::kStalled);
  EXPECT_EQ(in_ica->travelled_mm(), 0.0);
  ASSERT_LT(a1_open * a1_arrested, 0.0) << "the A1's flow reverses";
  const double a1_length = net->segments()[a1].length_mm;
  auto in_a1 = EmbolusTransit::start(*net, Fragment{{a1, 0.5 * a1_length, 0.0}, 1.0, 2.0, kReferenceComposition});
  ASSERT_TRUE(in_a1);
  for (int k = 0; k < 5000 && !in_a1->done(); ++k) in_a1->advance(*net, kTick_s);
  ASSERT_TRUE(in_a1->done());
  ASSERT_GE(in_a1->path().segments.size(), 2u);
  const std::string second = model.segments[in_a1->path().segments[1]].name;
  const std::string last = model.segments[in_a1->path().lodged.segment].name;
  std::printf("from the A1 under arrest: %s ... lodges in %s after %.1f ms\n", second.c_str(), last.c_str(), 1e3 * in_a1->elapsed_s());
  EXPECT_EQ(second, "left_middle_cerebral_m1");
  EXPECT_NE(last.find("left_middle_cerebral"), std::string::npos) << last;
}

// Griffith: the critical crack a_c = G_c E / (pi tau^2) (hand-computed), and a clot cut into
// pieces no longer than it. At the open neuro M1's wall shear the critical crack of the bundled
// M1 clot (60 % red cells / 30 % fibrin: Et75 290 kPa, E 7.25 kPa) is metres long: the flow
// carries a stripped clot whole (G_c 7.6 J/m^2, Tutwiler et al., Sci Adv 2020).
TEST(ClotFracture, GriffithCriticalCrackAndTheFlowCarriesAClotWhole) {
  const ClotComposition m1{60.0, 30.0};
  EXPECT_NEAR(clot_tensile_modulus_Pa(m1), 290e3 / 40.0, 1e-6);
  const double tau = 2000.0;  // Pa
  const double a_c = 1e3 * 7.6 * 7250.0 / (std::numbers::pi * tau * tau);
  EXPECT_NEAR(critical_crack_mm(m1, tau), a_c, 1e-9 * a_c);
  const Fragment whole{{0, 0.0, 0.0}, 2.9, 13.0, m1};
  const std::vector<Fragment> pieces = fragments_in_flow(whole, tau);
  ASSERT_EQ(pieces.size(), static_cast<std::size_t>(std::ceil(13.0 / a_c)));
  for (const Fragment& p : pieces) EXPECT_LE(p.length_mm, a_c);
  EXPECT_EQ(fragments_in_flow(whole, 0.0).size(), 1u);

  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const auto m1_seg = static_cast<std::uint32_t>(*model.index_of(22));
  const double shear = wall_shear_Pa(*net, {m1_seg, 5.0, 0.0});
  std::printf("left M1 wall shear %.2f Pa: critical crack %.0f m for the M1 clot\n", shear, 1e-3 * critical_crack_mm(m1, shear));
  EXPECT_GT(shear, 1.0);   // arterial wall shear: 1-10 Pa
  EXPECT_LT(shear, 40.0);
  EXPECT_GT(critical_crack_mm(m1, shear), 1000.0 * 13.0);
  EXPECT_EQ(fragments_in_flow(whole, shear).size(), 1u);
}

}  // namespace
}  // namespace cathbox::flow

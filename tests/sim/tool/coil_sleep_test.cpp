// Sleeping released coils (tool/coil_sleep.hpp), in virtual time: a coil left alone in a free
// sphere falls asleep and stays where the coil solved every step would be, within the creep its
// rest test admits; a sleeping coil wakes when a second coil is pushed against it, and the run
// then differs from one without sleeping only by that creep; it wakes when the wall it rests on
// moves (the pulse); a run with sleeps is repeated bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "tool/displaced_wall.hpp"
#include "tool/simulator.hpp"
#include "analytic_walls.hpp"
#include "coil_release.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {
namespace {

// A parent artery (radius 1 mm along z) opening into a free sphere of the bundled sac's size.
constexpr double kSphereR = testing::kSacSphereR, kNeckR = testing::kSacNeckR;
const glm::dvec3 kCentre = testing::kSacCentre;
constexpr double kCoilLength = 40.0;
constexpr double kLoopD = 4.0;
const Entry kEntry{{0, 0, -3}, {0, 0, 1}};
const double kMicroDepth = kCentre.z - std::sqrt(kSphereR * kSphereR - kNeckR * kNeckR) + 1.0 - kEntry.point_mm.z;
constexpr std::size_t kMicro = 0, kFirst = 1, kSecond = 2;
// How much further the sleeping run may be from the run without sleeping than the runs pushed
// 1 um deeper and 1 um shallower are (measured: see the test's print).
constexpr double kStrikeGain = 2.0;

// A parent artery (radius 1 mm along z) opening into a free sphere.
TubeNetworkWall sphere_on_a_tube() { return testing::sphere_on_a_tube(kSphereR, kNeckR, kCentre); }

std::vector<ToolSpec> micro_and_two_coils() {
  ToolSpec first = default_coil(kCoilLength, kLoopD), second = default_coil(kCoilLength, kLoopD);
  first.name = "coil 1";
  second.name = "coil 2";
  return {default_microcatheter(), first, second};
}

void drive(Simulator& sim, std::size_t tool, double target, double per_step) {
  while (std::abs(sim.insertion_mm(tool) - target) > 1e-9) {
    const double d = std::clamp(target - sim.insertion_mm(tool), -per_step, per_step);
    sim.set_insertion(tool, sim.insertion_mm(tool) + d);
    sim.step();
  }
}

// The microcatheter's tip 1 mm into the sphere; the first coil pushed out at 20 mm/s, released,
// its pusher drawn back; the second coil at the microcatheter's tip.
void release_first(Simulator& sim) {
  drive(sim, kMicro, kMicroDepth, 0.2);
  drive(sim, kFirst, kMicroDepth - 0.5, 0.2);
  drive(sim, kSecond, kMicroDepth - 20.0, 0.2);
  drive(sim, kFirst, kMicroDepth + kCoilLength + 1.0, 0.02);
  ASSERT_EQ(testing::release_coil(sim, kFirst), DeviceError::kNone);
  drive(sim, kFirst, kMicroDepth - 10.0, 0.2);
}

double largest_distance(std::span<const glm::dvec3> a, std::span<const glm::dvec3> b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, glm::length(a[k] - b[k]));
  return worst;
}

// How far a sleeping coil may be from the same coil solved every step: a coil falls asleep only
// after a window of rest_ticks steps in which no node drifted, net, more than drift_share of its
// solver tolerance (2 um in 0.2 s); solved on, a coil still relaxing may go on at up to
// kCreepGain times that rate (a 40 mm coil left alone, released coils' warm start 0.5: 1.46
// times), plus one window for the window it fell asleep in.
constexpr double kCreepGain = 2.0;
double creep_bound_mm(Simulator& sim, std::uint64_t skipped_steps) {
  const CoilSleep::Settings& s = sim.coil_sleep_settings();
  const double per_window = s.drift_share * sim.detached(0).settings().convergence_mm;
  return per_window * (kCreepGain * static_cast<double>(skipped_steps) / s.rest_ticks + 1.0);
}

// Steps both runs until the first coil sleeps in `sim` (at most `limit` steps).
void until_asleep(Simulator& sim, Simulator* solved, int limit) {
  for (int i = 0; i < limit && sim.coil_sleep().asleep_count() == 0; ++i) {
    sim.step();
    if (solved != nullptr) solved->step();
  }
}

// Left alone for 8 s, the released coil falls asleep; the same coil solved every step (sleeping
// off) ends within the creep the rest test admits of where it sleeps (creep_bound_mm). Asleep it
// is not solved: a sixth of its steps and more are skipped.
TEST(CoilSleep, ACoilLeftAloneSleepsWhereTheCoilSolvedEveryStepRests) {
  const TubeNetworkWall wall = sphere_on_a_tube();
  const std::vector<ToolSpec> tools = micro_and_two_coils();
  Simulator sleeping(wall, tools, kEntry), solved(wall, tools, kEntry);
  solved.coil_sleep_settings().enabled = false;
  release_first(sleeping);
  release_first(solved);
  ASSERT_EQ(largest_distance(sleeping.detached(0).positions(), solved.detached(0).positions()), 0.0);
  for (int i = 0; i < 8000; ++i) {
    sleeping.step();
    solved.step();
  }
  EXPECT_EQ(sleeping.coil_sleep().asleep_count(), 1u);
  EXPECT_EQ(solved.coil_sleep().asleep_count(), 0u);
  const std::uint64_t skipped = sleeping.coil_sleep().skipped_steps();
  EXPECT_GT(skipped, 8000u / 6);
  const double apart = largest_distance(sleeping.detached(0).positions(), solved.detached(0).positions());
  const double bound = creep_bound_mm(sleeping, skipped);
  EXPECT_LT(apart, bound) << "the sleeping coil is " << 1e3 * apart << " um from the solved one";
  std::printf("coil left alone 8 s: %llu of its steps skipped, %.4f um from the coil solved every step (bound %.4f um)\n",
              static_cast<unsigned long long>(skipped), 1e3 * apart, 1e3 * bound);
}

// A sleeping coil is an obstacle the next coil would only press into: pushed against it, the
// second coil wakes it and it moves, and the two stay apart. The wake is decided before the
// sleeping coil's solve from the rods solved before it, so the run differs from one without
// sleeping (every coil solved every step) only by where the first coil crept while asleep (about
// a micrometre): pushed in, the coils amplify that as they amplify any micrometre, so the
// sleeping run is compared with the run without sleeping as closely as two more runs, without
// sleeping and pushed 1 um deeper and 1 um shallower, are: the pushed coil's hand force and both
// coils' nodes. Both signs: the creep has no direction along the push, and what the contacts
// make of a micrometre depends on its sign (with the wall against edges at the sac's neck rim,
// the pushed coil's hand force 1.36 mN from the run without sleeping pushed 1 um deeper, 4.14
// mN 1 um shallower, 2.85 and 3.32 mN 0.5 and 2 um deeper; the sleeping run's 2.83).
TEST(CoilSleep, ASleepingCoilWakesWhenTheNextCoilPushesIt) {
  const TubeNetworkWall wall = sphere_on_a_tube();
  const std::vector<ToolSpec> tools = micro_and_two_coils();
  Simulator sim(wall, tools, kEntry), solved(wall, tools, kEntry), deeper(wall, tools, kEntry), shallower(wall, tools, kEntry);
  for (Simulator* s : {&solved, &deeper, &shallower}) s->coil_sleep_settings().enabled = false;
  for (Simulator* s : {&sim, &solved, &deeper, &shallower}) release_first(*s);
  for (int i = 0; i < 8000 && sim.coil_sleep().asleep_count() == 0; ++i) {
    for (Simulator* s : {&sim, &solved, &deeper, &shallower}) s->step();
  }
  ASSERT_EQ(sim.coil_sleep().asleep_count(), 1u) << "the released coil did not fall asleep in 8 s";
  const std::vector<glm::dvec3> asleep(sim.detached(0).positions().begin(), sim.detached(0).positions().end());
  for (Simulator* s : {&sim, &solved, &deeper, &shallower}) drive(*s, kSecond, kMicroDepth - 0.5, 0.2);
  EXPECT_EQ(sim.coil_sleep().wakes(), 0u) << "the second coil woke it before leaving the microcatheter";
  const double asleep_apart = largest_distance(sim.detached(0).positions(), solved.detached(0).positions());
  struct Apart {
    double force = 0.0, first = 0.0, second = 0.0;
    void add(const Simulator& a, const Simulator& b) {
      force = std::max(force, std::abs(a.rod(kSecond).hand_force_mN() - b.rod(kSecond).hand_force_mN()));
      first = std::max(first, largest_distance(a.detached(0).positions(), b.detached(0).positions()));
      // The second coil's free nodes (those on the entry line depend on the insertion alone).
      const Rod& ra = a.rod(kSecond);
      const Rod& rb = b.rod(kSecond);
      const std::size_t from = std::max(ra.first_free_node(), rb.first_free_node());
      second = std::max(second, largest_distance(ra.positions().subspan(from), rb.positions().subspan(from)));
    }
  } slept, pushed;
  constexpr double kNudge_mm = 1e-3;
  double peak = 0.0;
  while (sim.insertion_mm(kSecond) < kMicroDepth + kCoilLength + 1.0 - 1e-9) {
    const double next = std::min(kMicroDepth + kCoilLength + 1.0, sim.insertion_mm(kSecond) + 0.02);
    sim.set_insertion(kSecond, next);
    solved.set_insertion(kSecond, next);
    deeper.set_insertion(kSecond, next + kNudge_mm);
    shallower.set_insertion(kSecond, next - kNudge_mm);
    for (Simulator* s : {&sim, &solved, &deeper, &shallower}) s->step();
    slept.add(sim, solved);
    pushed.add(deeper, solved);
    pushed.add(shallower, solved);
    peak = std::max(peak, std::abs(solved.rod(kSecond).hand_force_mN()));
  }
  EXPECT_GE(sim.coil_sleep().wakes(), 1u);
  const double moved = largest_distance(sim.detached(0).positions(), asleep);
  EXPECT_GT(moved, 0.01) << "the first coil moved " << moved << " mm while the second was pushed in";
  const RodContactField::Overlap o = sim.worst_coil_overlap();
  EXPECT_LT(o.depth_mm, 0.1 * o.diameter_mm + 1e-12) << "loops overlap by " << o.depth_mm << " mm";
  std::printf("second coil pushed in: %llu wakes, the first coil moved up to %.3f mm, overlap %.4f mm\n",
              static_cast<unsigned long long>(sim.coil_sleep().wakes()), moved, o.depth_mm);
  std::printf("against the run without sleeping (hand force %.3f mN at most): %.4f um apart when struck; "
              "with sleeping the second's hand force %.4f mN, its nodes %.2f um, the first's %.2f um; "
              "pushed 1 um deeper or shallower %.4f mN, %.2f um, %.2f um\n",
              peak, 1e3 * asleep_apart, slept.force, 1e3 * slept.second, 1e3 * slept.first, pushed.force,
              1e3 * pushed.second, 1e3 * pushed.first);
  EXPECT_LT(asleep_apart, creep_bound_mm(sim, sim.coil_sleep().skipped_steps()));
  EXPECT_LT(slept.force, kStrikeGain * pushed.force);
  EXPECT_LT(slept.second, kStrikeGain * pushed.second);
  EXPECT_LT(slept.first, kStrikeGain * pushed.first);
}

// A wall that moves in place (a displaced wall: the pulse of a compliant vessel) wakes every
// sleeping coil at once, and the woken coil follows the wall as the coil solved every step does
// (within the creep the rest test admits, as above); a wall that moves every step (as the
// pulse does) never lets a coil sleep. A displaced wall that stays put lets it sleep as before.
TEST(CoilSleep, AWallThatMovesWakesTheCoilsAsleepOnIt) {
  const TubeNetworkWall tubes = sphere_on_a_tube();
  DisplacedWall wall(tubes), solved_wall(tubes);
  const std::vector<ToolSpec> tools = micro_and_two_coils();
  Simulator sim(wall, tools, kEntry), solved(solved_wall, tools, kEntry);
  solved.coil_sleep_settings().enabled = false;
  release_first(sim);
  release_first(solved);
  until_asleep(sim, &solved, 8000);
  ASSERT_EQ(sim.coil_sleep().asleep_count(), 1u) << "the released coil did not fall asleep in 8 s on a still wall";
  const std::vector<glm::dvec3> asleep(sim.detached(0).positions().begin(), sim.detached(0).positions().end());
  const double bound = creep_bound_mm(sim, sim.coil_sleep().skipped_steps());
  wall.set_uniform_mm(-0.5);  // the sac drawn in 0.5 mm
  solved_wall.set_uniform_mm(-0.5);
  sim.step();
  solved.step();
  EXPECT_EQ(sim.coil_sleep().asleep_count(), 0u);
  EXPECT_EQ(sim.coil_sleep().wakes(), 1u);
  for (int i = 0; i < 1000; ++i) {  // a 1 Hz pulse of 20 um (sampled every 1 ms)
    const double w = -0.5 + 0.02 * std::sin(2.0 * 3.141592653589793 * i / 1000.0);
    wall.set_uniform_mm(w);
    solved_wall.set_uniform_mm(w);
    sim.step();
    solved.step();
    ASSERT_EQ(sim.coil_sleep().asleep_count(), 0u) << "a coil slept on a pulsing wall at step " << i;
  }
  const double moved = largest_distance(sim.detached(0).positions(), asleep);
  const double apart = largest_distance(sim.detached(0).positions(), solved.detached(0).positions());
  EXPECT_LT(apart, bound) << "the woken coil is " << 1e3 * apart << " um from the coil solved every step";
  std::printf("wall drawn in 0.5 mm under a sleeping coil, then pulsing: it woke, moved up to %.3f mm, %.4f um from the coil solved every step\n",
              moved, 1e3 * apart);
}

// Sleep and wake read only the rods' positions: the same inputs give the same run, step for
// step, bit for bit (a record replays with its state hashes).
TEST(CoilSleep, ARunWithSleepsRepeatsBitForBit) {
  const TubeNetworkWall wall = sphere_on_a_tube();
  const std::vector<ToolSpec> tools = micro_and_two_coils();
  Simulator a(wall, tools, kEntry), b(wall, tools, kEntry);
  release_first(a);
  release_first(b);
  std::size_t asleep_steps = 0;
  for (int i = 0; i < 9000; ++i) {
    if (i >= 7000) {  // the second coil to the microcatheter's tip, then 20 mm out at 20 mm/s
      const double now = a.insertion_mm(kSecond);
      const double next = std::min(kMicroDepth + 20.0, now + (now < kMicroDepth - 0.5 ? 0.2 : 0.02));
      a.set_insertion(kSecond, next);
      b.set_insertion(kSecond, next);
    }
    a.step();
    b.step();
    ASSERT_EQ(a.coil_sleep().asleep(0), b.coil_sleep().asleep(0)) << "step " << i;
    ASSERT_EQ(largest_distance(a.detached(0).positions(), b.detached(0).positions()), 0.0) << "step " << i;
    ASSERT_EQ(largest_distance(a.rod(kSecond).positions(), b.rod(kSecond).positions()), 0.0) << "step " << i;
    asleep_steps += a.coil_sleep().asleep(0) ? 1 : 0;
  }
  EXPECT_GT(asleep_steps, 0u);
  EXPECT_EQ(a.coil_sleep().wakes(), b.coil_sleep().wakes());
}

}  // namespace
}  // namespace cathbox::tool

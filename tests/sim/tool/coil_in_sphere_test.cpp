// A coil released in a free sphere of the bundled sac's size, in virtual time: it stays in it and
// forms loops of its rest diameter, comes to rest left alone, fills the analytic packing density,
// and no loop passes into another over 10^4 random push/pull/rotate steps; the rod-rod candidate
// list and the two sides of a self-contact.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "collision/segment_pair.hpp"
#include "tool/aneurysm_sac.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/simulator.hpp"

#include "coil_test_support.hpp"

namespace cathbox::tool {
namespace {

using namespace testing;  // coil_test_support.hpp: the sphere, the tools, drive and the packing checks

// Mean diameter of the circle through nodes k - m, k, k + m along a coil.
double mean_loop_diameter(std::span<const glm::dvec3> x, std::size_t first, std::size_t last, std::size_t m) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = first + m; k + m < last; ++k) {
    const glm::dvec3 a = x[k - m] - x[k], b = x[k + m] - x[k], c = x[k + m] - x[k - m];
    const double area2 = glm::length(glm::cross(a, b));
    if (area2 < 1e-12) continue;
    sum += glm::length(a) * glm::length(b) * glm::length(c) / area2;  // 2 R = abc / (2 area)
    ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

// The microcatheter's tip 1 mm into the free sphere, the coil at its tip, the sac's metrics.
class CoilInSphere : public ::testing::Test {
 protected:
  TubeNetworkWall wall = sphere_on_a_tube();
  std::vector<ToolSpec> tools = micro_and_coil();
  Simulator sim{wall, tools, kEntry};
  AneurysmSac sac = *sphere_cap_sac(kCentre, kSphereR, {0, 0, kNeckZ});
  CoilMetrics metrics{sim, sac};
  double micro = place_microcatheter(sim);
};

TEST_F(CoilInSphere, CoilReleasedInAFreeSphereStaysInsideAndFormsLoopsOfItsRestDiameter) {
  // Push the whole coil out (its detachment zone 1 mm past the tip) at 20 mm/s, detach, and let
  // it settle for 2 s (the soft coil relaxes against the solver's damping).
  drive(sim, kCoil, micro + kCoilLength + 1.0, 0.02, &metrics);
  ASSERT_EQ(release_coil(sim, kCoil), DeviceError::kNone);
  for (int i = 0; i < 2000; ++i) {
    sim.step();
    metrics.observe(sim);
  }
  ASSERT_EQ(sim.detached_count(), 1u);
  const Rod& coil = sim.detached(0);
  EXPECT_NEAR(coil.length_mm(), kCoilLength, 0.3);
  // Inside: every node within the sphere (less 10 % of its radius of slack), none herniated.
  const std::span<const glm::dvec3> x = coil.positions();
  double worst = 0.0;
  for (const glm::dvec3& p : x) {
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    worst = std::max(worst, glm::length(p - kCentre) + 0.5 * kCoilOd - kSphereR);
    EXPECT_GT(sac.depth_mm(p), -0.5 * kCoilOd);
  }
  EXPECT_LT(worst, 0.1 * 0.5 * kCoilOd) << "a node is " << worst << " mm outside the sphere";
  EXPECT_EQ(metrics.figures().herniations, 0);
  // Loops of the rest diameter within 10 %: circles through nodes 3 mm apart along the coil.
  const double d = mean_loop_diameter(x, 2, x.size() - 2, 6);
  EXPECT_NEAR(d / kLoopD, 1.0, 0.10) << "mean loop diameter " << d << " mm";
  std::printf("free sphere: mean loop diameter %.3f mm, deepest node %.4f mm out\n", d, worst);
}

// The largest node move of the released coil over each of `ticks` steps from `from` on, as a
// speed: a move on its turn over the ticks the turn covers (Simulator::set_released_turn_ticks).
struct Settling {
  double late_um_per_tick = 0.0;  // the largest, over the window
  int moved_off_turn = 0;         // steps that moved it off its turns
};
Settling settle(Simulator& sim, int from, int ticks) {
  Settling out;
  const auto turn = static_cast<double>(sim.released_turn_ticks());
  for (int i = 0; i < from + ticks; ++i) {
    const std::span<const glm::dvec3> x = sim.detached(0).positions();
    const std::vector<glm::dvec3> before(x.begin(), x.end());
    const bool on_turn = sim.released_coil_turn(0);
    sim.step();
    const std::span<const glm::dvec3> after = sim.detached(0).positions();
    double worst_mm = 0.0;
    for (std::size_t k = 0; k < after.size(); ++k) worst_mm = std::max(worst_mm, glm::length(after[k] - before[k]));
    if (!on_turn) out.moved_off_turn += worst_mm > 0.0 ? 1 : 0;
    if (i >= from) out.late_um_per_tick = std::max(out.late_um_per_tick, 1e3 * worst_mm / turn);
  }
  return out;
}

// A coil released in the sphere and left alone comes to rest: quasi-static, with nothing moving
// it, its energy has a minimum and each step's solve only descends. Its largest node move from 6
// to 8 s after release is under 0.1 um a tick (1e-4 mm, 1/2500 of its 0.25 mm diameter); it was
// 8-18 um while the position solve did not see the twist's load on the centreline and the twist
// minimised another bending energy (docs/sim-tool/convergence.md). Solved on its turns (every
// second tick over both), the coil slips on the sphere once more 4.5 s after release (1.0 um in a
// turn); solved every tick it reads 0.02 um a tick from 4 s on.
TEST_F(CoilInSphere, ReleasedCoilLeftAloneComesToRest) {
  sim.coil_sleep_settings().enabled = false;  // solved on every turn (asleep it would not move at all)
  drive(sim, kCoil, micro + kCoilLength + 1.0, 0.02);
  ASSERT_EQ(release_coil(sim, kCoil), DeviceError::kNone);
  const Settling s = settle(sim, 6000, 2000);
  EXPECT_LT(s.late_um_per_tick, 0.1) << "a node moved " << s.late_um_per_tick << " um a tick 6-8 s after release";
  std::printf("released coil 6-8 s after release: largest node move %.5f um a tick\n", s.late_um_per_tick);
}

// Released coils are solved on their turns (Simulator::set_released_turn_ticks: every second
// tick, over both ticks' time), and a turn is an implicit (backward Euler) step, stable at any
// length, whose fixed point is the static equilibrium: off its turns the coil does not move, and
// on them it relaxes to its stress-free loops (the analytic rest diameter, as the coil solved
// every tick does) and comes to rest. Where in the sphere it rests depends on its path, as any
// micrometre's difference makes a coil's frictional rest do (CoilSleep's strike test).
TEST_F(CoilInSphere, ReleasedCoilSolvedOnItsTurnsRelaxesToItsLoopsAsOneSolvedEveryTick) {
  ASSERT_EQ(sim.released_turn_ticks(), 2u);
  Simulator every{wall, tools, kEntry};
  every.set_released_turn_ticks(1);
  const double micro_every = place_microcatheter(every);
  for (Simulator* s : {&sim, &every}) {
    s->coil_sleep_settings().enabled = false;
    drive(*s, kCoil, (s == &sim ? micro : micro_every) + kCoilLength + 1.0, 0.02);
    ASSERT_EQ(release_coil(*s, kCoil), DeviceError::kNone);
  }
  const Settling turns = settle(sim, 6000, 2000), each = settle(every, 6000, 2000);
  EXPECT_EQ(turns.moved_off_turn, 0);
  EXPECT_LT(turns.late_um_per_tick, 0.1);
  EXPECT_LT(each.late_um_per_tick, 0.1);
  const std::span<const glm::dvec3> a = sim.detached(0).positions(), b = every.detached(0).positions();
  const double da = mean_loop_diameter(a, 2, a.size() - 2, 6), db = mean_loop_diameter(b, 2, b.size() - 2, 6);
  EXPECT_NEAR(da / kLoopD, 1.0, 0.10) << "solved on its turns: mean loop diameter " << da << " mm";
  EXPECT_NEAR(da / db, 1.0, 0.02) << "solved every tick: " << db << " mm";
  std::printf("released coil at 8 s: mean loop diameter %.3f mm solved on its turns, %.3f mm every tick (rest %.1f); "
              "6-8 s: %.5f and %.5f um a tick\n", da, db, kLoopD, turns.late_um_per_tick, each.late_um_per_tick);
}

TEST_F(CoilInSphere, PackingDensityIsTheAnalyticCoilVolumeOverTheSac) {
  metrics.observe(sim);
  EXPECT_EQ(metrics.figures().deployed_mm, 0.0);
  // Half the coil out: the deployed length is the coil's advance past the catheter's tip.
  const double start = sim.insertion_mm(kCoil);
  drive(sim, kCoil, micro + 20.0, 0.02, &metrics);
  const double analytic_half = M_PI / 4.0 * kCoilOd * kCoilOd * 20.0;
  EXPECT_NEAR(metrics.figures().deployed_mm, 20.0, 0.5) << "pushed " << sim.insertion_mm(kCoil) - start;
  EXPECT_NEAR(metrics.figures().coil_volume_mm3 / analytic_half, 1.0, 0.03);
  // All of it, released: pi/4 d^2 L over the sphere cap's volume.
  drive(sim, kCoil, micro + kCoilLength + 1.0, 0.02, &metrics);
  ASSERT_EQ(release_coil(sim, kCoil), DeviceError::kNone);
  for (int i = 0; i < 50; ++i) {
    sim.step();
    metrics.observe(sim);
  }
  const double cap = sphere_cap_volume_mm3(kSphereR, kSphereR + (kCentre.z - kNeckZ));
  const double analytic = M_PI / 4.0 * kCoilOd * kCoilOd * kCoilLength / cap;
  EXPECT_NEAR(metrics.figures().packing_density / analytic, 1.0, 0.01);
  EXPECT_NEAR(metrics.figures().deployed_mm, kCoilLength, 0.3);
  // The coil's volume from its own centre line (edge lengths): it did not stretch.
  const std::span<const glm::dvec3> x = sim.detached(0).positions();
  double arc = 0.0;
  for (std::size_t k = 1; k < x.size(); ++k) arc += glm::length(x[k] - x[k - 1]);
  EXPECT_NEAR(arc / kCoilLength, 1.0, 0.02);
  // The simulator refuses a second detach: the pusher alone stays.
  EXPECT_EQ(sim.detach(kCoil), DeviceError::kNotACoil);
}

// The detach force (CoilMetrics: the pusher's push on its coil where it leaves the microcatheter,
// on the last step before the detach command starts the zone parting): the coil pushed out (its
// detachment zone 1 mm past the tip), held at rest 0.3 s, then detached and released. Free in the sphere it is released in neutral (a few
// mN: the loops' own spring); with the coil mass pressing back on the pusher (a 200 mN load on
// the coil's proximal node, back along the catheter's axis: the bundled frame's 203 mN push held
// against the dome at its markers, docs/sim-tool/convergence.md, "Detaching in neutral") it is
// released under tension, and reads that load. A coil is to be detached in neutral, its markers
// aligned and the delivery wire neither pushing nor pulling (Kwon & Han, AJNR 23(8):1276, 2002, on
// the alignment; detachable-coil instructions for use on the tension): a load let go of in one
// step moves the microcatheter and the coil.
double push_on_coil_mN(const Simulator& sim, std::size_t t) {
  return sim.hand_force_mN(t) - sim.sheath(t).force_mN - sim.valve(t).force_mN;
}

double detach_after_rest(Simulator& sim, CoilMetrics& metrics, double load_mN) {
  drive(sim, kCoil, sim.insertion_mm(kMicro) + kCoilLength + 1.0, 0.02, &metrics);
  std::size_t proximal = 0;  // the coil's proximal node (its detachment zone)
  while (proximal + 1 < sim.rod(kCoil).node_total() && sim.rod(kCoil).node_from_tip_mm(proximal) > kCoilLength + 1e-9) ++proximal;
  sim.set_node_load(kCoil, proximal, {0.0, 0.0, -load_mN});
  for (int i = 0; i < 300; ++i) {
    sim.step();
    metrics.observe(sim);
  }
  const double before = push_on_coil_mN(sim, kCoil);
  sim.set_node_load(kCoil, proximal, {0.0, 0.0, 0.0});
  EXPECT_EQ(release_coil(sim, kCoil, &metrics), DeviceError::kNone);
  for (int i = 0; i < 20; ++i) {
    sim.step();
    metrics.observe(sim);
  }
  return before;
}

TEST_F(CoilInSphere, TheDetachForceIsThePushersLoadOnItsCoilAtTheRelease) {
  EXPECT_EQ(metrics.figures().detachments, 0);
  const double neutral = detach_after_rest(sim, metrics, 0.0);
  const CoilFigures& f = metrics.figures();
  ASSERT_EQ(f.detachments, 1);
  EXPECT_DOUBLE_EQ(f.detach_force_mN[0], neutral);
  EXPECT_LT(std::abs(f.detach_force_mN[0]), CoilMetrics::kNeutral_mN);
  EXPECT_EQ(f.detached_under_tension, 0);

  Simulator loaded_sim{wall, tools, kEntry};
  CoilMetrics loaded{loaded_sim, sac};
  place_microcatheter(loaded_sim);
  const double tension = detach_after_rest(loaded_sim, loaded, 200.0);
  const CoilFigures& g = loaded.figures();
  ASSERT_EQ(g.detachments, 1);
  EXPECT_DOUBLE_EQ(g.detach_force_mN[0], tension);
  EXPECT_NEAR(g.detach_force_mN[0], 200.0, 30.0);
  EXPECT_EQ(g.detached_under_tension, 1);
  EXPECT_DOUBLE_EQ(g.detach_force_peak_mN, std::abs(tension));
  // After the release the pusher alone carries no coil: the metric keeps the value at the release.
  EXPECT_LT(std::abs(push_on_coil_mN(loaded_sim, kCoil)), CoilMetrics::kNeutral_mN);
  std::printf("detach force: in neutral %+.1f mN, the coil pressing back with 200 mN %+.1f mN\n", neutral, tension);
}

TEST_F(CoilInSphere, NoLoopPassesIntoAnotherOverRandomPushPullRotateSteps) {
  drive(sim, kCoil, micro + 0.6 * kCoilLength, 0.02);
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> push(-0.05, 0.06), turn(-0.05, 0.05);
  std::uniform_int_distribution<int> what(0, 2);
  double worst = 0.0;
  int worst_step = -1;
  const double lo = micro + 0.2 * kCoilLength, hi = micro + 0.9 * kCoilLength;
  for (int i = 0; i < 10000; ++i) {
    const int w = what(rng);
    if (w < 2) {
      sim.set_insertion(kCoil, std::clamp(sim.insertion_mm(kCoil) + push(rng), lo, hi));
    } else {
      sim.set_rotation(kCoil, sim.rotation_rad(kCoil) + turn(rng));
    }
    sim.step();
    const RodContactField::Overlap o = sim.worst_coil_overlap();
    if (o.diameter_mm > 0.0 && o.depth_mm / o.diameter_mm > worst) {
      worst = o.depth_mm / o.diameter_mm;
      worst_step = i;
    }
    ASSERT_TRUE(std::isfinite(sim.tip(kCoil).position_mm.x)) << "step " << i;
  }
  EXPECT_LT(worst, 0.10) << "deepest overlap " << 100.0 * worst << " % of the coil diameter at step " << worst_step;
  std::printf("random steps: deepest overlap %.2f %% of the coil diameter\n", 100.0 * worst);
}

// The contacts of `field` for each of its members, and its worst overlap, against those of a
// field built afresh at the present positions with no skin; the contacts compared, added to
// `compared`.
void expect_the_same_contacts(const std::vector<EdgeContact>& kept, const std::vector<EdgeContact>& fresh, int step) {
  ASSERT_EQ(kept.size(), fresh.size()) << "step " << step;
  for (std::size_t c = 0; c < kept.size(); ++c) {
    ASSERT_EQ(kept[c].edge, fresh[c].edge) << "step " << step;
    ASSERT_EQ(kept[c].s, fresh[c].s) << "step " << step;
    ASSERT_EQ(kept[c].normal, fresh[c].normal) << "step " << step;
    ASSERT_EQ(kept[c].offset_mm, fresh[c].offset_mm) << "step " << step;
  }
}

// The fresh field lists each member from its first gathered edge (no Member::listed_first).
void expect_the_contacts_of_a_fresh_list(const RodContactField& field, int step, std::size_t& compared) {
  std::vector<EdgeContact> kept, fresh;
  RodContactField afresh(field.margin_mm(), 0.0);
  std::vector<RodContactField::Member> members(field.members().begin(), field.members().end());
  for (RodContactField::Member& m : members) m.listed_first = m.edge_first;
  afresh.set_members(members);
  for (const RodContactField::Member& m : field.members()) {
    field.gather(*m.rod, kept);
    afresh.gather(*m.rod, fresh);
    expect_the_same_contacts(kept, fresh, step);
    if (::testing::Test::HasFatalFailure()) return;
    compared += kept.size();
  }
  ASSERT_EQ(field.worst_overlap().depth_mm, afresh.worst_overlap().depth_mm) << "step " << step;
}

// The rod-rod candidate list (a Verlet list kept while the edges move less than half its skin,
// its pairs skipped while their last distance less what their ends moved since keeps them out
// of reach) gives exactly the contacts of a list built afresh at the present positions with no
// skin, for every member rod and at every step of random pushes, pulls and turns; it is not
// rebuilt at every step.
TEST_F(CoilInSphere, CandidateListGivesTheContactsOfAListBuiltAfresh) {
  drive(sim, kCoil, micro + 0.5 * kCoilLength, 0.02);
  std::mt19937 rng(7);
  // Turns most of the time; a push or pull that takes a node in or out of the simulated part
  // moves the members' edge ranges (the list carried over to them).
  std::uniform_real_distribution<double> push(-0.05, 0.08), turn(-0.2, 0.2);
  std::uniform_int_distribution<int> what(0, 9);
  const RodContactField& field = sim.coil_contacts();
  const std::uint64_t builds0 = field.list_builds();
  std::size_t compared = 0;
  constexpr int kSteps = 1500;
  for (int i = 0; i < kSteps; ++i) {
    if (what(rng) == 0) {
      sim.set_insertion(kCoil, sim.insertion_mm(kCoil) + push(rng));
    } else {
      sim.set_rotation(kCoil, sim.rotation_rad(kCoil) + turn(rng));
    }
    sim.step();
    expect_the_contacts_of_a_fresh_list(field, i, compared);
    if (HasFatalFailure()) return;
  }
  // The coil touches itself: ~7.7 contacts a step (11,524 in all). With 0.4 of the coil out
  // (16 mm) it did ~6 (9,724) while the coil bent at its clamp node, 2,226 once it bent from the
  // catheter's tip (RodSettings::clamp_hinge_at_entry): its second loop not yet on the first.
  EXPECT_GT(compared, 8000u);
  EXPECT_LT(field.list_builds() - builds0, static_cast<std::uint64_t>(kSteps / 2));
}

// A node of the coil crossing the microcatheter's tip moves its member's first gathered edge.
// The coil's member is listed from a multiple of 16 edges (Member::listed_first, the edges in the
// catheter before its tip listed, never gathered): 15 of 16 crossings keep the list as it is, and
// the one that moves the listed range carries the list over (the edges that stay keep their
// listed places, their pairs and last gaps), the build it calls for listing only the new edges
// and those that moved, not all (a full build of a packed sac at every crossing was the coil
// benches' slowest steps). The contacts stay those of a fresh list from the first gathered edge
// at every step.
TEST_F(CoilInSphere, ANodeCrossingTheCathetersTipKeepsOrCarriesTheListOver) {
  drive(sim, kCoil, micro + 0.6 * kCoilLength, 0.02);
  const RodContactField& field = sim.coil_contacts();
  const std::uint64_t carries0 = field.list_carries();
  std::size_t compared = 0, carried_builds = 0, relisted = 0, items = 0, crossings = 0;
  for (int i = 0; i < 1000; ++i) {  // 20 mm at 0.02 mm a step: 40 node crossings
    const std::uint64_t carries = field.list_carries(), builds = field.list_builds();
    const std::size_t first = sim.rod(kCoil).first_edge();
    sim.set_insertion(kCoil, sim.insertion_mm(kCoil) + 0.02);
    sim.step();
    crossings += sim.rod(kCoil).first_edge() != first ? 1 : 0;
    expect_the_contacts_of_a_fresh_list(field, i, compared);
    if (HasFatalFailure()) return;
    if (field.list_carries() > carries && field.list_builds() == builds + 1) {
      ++carried_builds;
      EXPECT_LT(field.relisted_by_last_build(), field.items()) << "step " << i;  // a partial build
      relisted += field.relisted_by_last_build();
      items += field.items();
    }
  }
  EXPECT_GE(crossings, 38u);
  const std::uint64_t carried = field.list_carries() - carries0;
  std::printf("%zu crossings, %llu carried over, %zu of %zu items listed again by their builds\n", crossings,
              static_cast<unsigned long long>(carried), relisted, items);
  EXPECT_GE(carried, 2u);
  EXPECT_LE(carried, 4u) << "of " << crossings << " crossings";
  EXPECT_EQ(carried_builds, carried);
  EXPECT_LT(relisted, items / 2);  // the new edges and those near the tip, pushed
  EXPECT_GT(compared, 2000u);
}

// Work done ahead, between steps (Simulator::prepare_next_step, the haptic loop's wait): the
// candidate list built there once an edge has moved most of the way the list covers leaves the
// steps themselves building it seldom, and the results are those of a simulator never asked,
// bit for bit.
TEST_F(CoilInSphere, TheListBuiltBetweenStepsLeavesTheStepsAndTheirResultsAlone) {
  Simulator ahead{wall, tools, kEntry};  // driven the same way; only this one prepares
  const double micro_ahead = place_microcatheter(ahead);
  drive(sim, kCoil, micro + 0.5 * kCoilLength, 0.02);
  drive(ahead, kCoil, micro_ahead + 0.5 * kCoilLength, 0.02);
  const RodContactField& field = sim.coil_contacts();
  const RodContactField& prepared = ahead.coil_contacts();
  const std::uint64_t builds0 = field.list_builds(), prepared0 = prepared.list_builds();
  std::uint64_t in_steps = 0, between = 0;
  for (int i = 0; i < 600; ++i) {
    for (Simulator* s : {&sim, &ahead}) s->set_insertion(kCoil, s->insertion_mm(kCoil) + 0.02);
    sim.step();
    const std::uint64_t before = prepared.list_builds();
    ahead.step();
    in_steps += prepared.list_builds() - before;
    between += ahead.prepare_next_step() ? 1 : 0;
    ASSERT_EQ(sim.rod(kCoil).hand_force_mN(), ahead.rod(kCoil).hand_force_mN()) << "step " << i;
    const auto x = sim.rod(kCoil).positions();
    const auto y = ahead.rod(kCoil).positions();
    for (std::size_t k = 0; k < x.size(); ++k) ASSERT_EQ(x[k], y[k]) << "step " << i << " node " << k;
  }
  const std::uint64_t unprepared = field.list_builds() - builds0;
  std::printf("builds: %llu in the steps unprepared; prepared, %llu between and %llu in the steps\n",
              static_cast<unsigned long long>(unprepared), static_cast<unsigned long long>(between),
              static_cast<unsigned long long>(in_steps));
  EXPECT_GT(unprepared, 40u);  // 12 mm at 0.02 mm a step, a build every ~0.1 mm or so
  EXPECT_EQ(prepared.list_builds() - prepared0, in_steps + between);
  EXPECT_LT(in_steps, unprepared / 5) << between << " built between the steps";
}

// A pair of a coil's own edges is tested once per gather: both sides hold the same plane (normals
// exactly opposite, offsets summing to the two radii), not two planes that differ by rounding.
// (The coil driven here met that shared-node case once the clamp's weights changed: 156 of 160
// contacts counted paired under a one-mirror rule.)
TEST_F(CoilInSphere, TheTwoSidesOfASelfContactHoldOnePlane) {
  drive(sim, kCoil, micro + 0.95 * kCoilLength, 0.02);
  const Rod& coil = sim.rod(kCoil);
  RodContactField::Member m;
  m.rod = &coil;
  m.edge_first = coil.first_edge();
  m.edge_last = coil.node_total() - 1;
  m.self = true;
  RodContactField field(0.3);  // the coil alone: every contact is a self contact (a wide margin: many)
  field.set_members(std::span<const RodContactField::Member>(&m, 1));
  std::vector<EdgeContact> contacts;
  field.gather(coil, contacts);
  ASSERT_GT(contacts.size(), 20u);
  ASSERT_EQ(contacts.size() % 2, 0u);
  std::size_t paired = 0;
  const std::span<const glm::dvec3> x = coil.positions();
  for (const EdgeContact& c : contacts) {
    const double radius = 0.5 * (coil.node_radius_mm(c.edge) + coil.node_radius_mm(c.edge + 1));
    const auto same_plane = [&](const EdgeContact& o) {
      const double other = 0.5 * (coil.node_radius_mm(o.edge) + coil.node_radius_mm(o.edge + 1));
      return o.normal == -c.normal && std::abs(o.offset_mm + c.offset_mm - (radius + other)) < 1e-12;
    };
    // Where the closest point is the node two consecutive edges share, both give the edge across
    // the same plane, held twice on either side: the mirrors then match its copies one for one.
    const auto copy = [&](const EdgeContact& o) { return o.normal == c.normal && o.offset_mm == c.offset_mm; };
    const auto mirrors = std::count_if(contacts.begin(), contacts.end(), same_plane);
    paired += mirrors >= 1 && mirrors == std::count_if(contacts.begin(), contacts.end(), copy);
    // Either side (the tested or the mirrored one) equals the segment test made from its own edge:
    // its closest point on its edge, the normal from the other edge's closest point to it.
    const auto o = std::find_if(contacts.begin(), contacts.end(), same_plane);
    if (o == contacts.end()) continue;
    const collision::SegmentPair pair = collision::closest_segment_segment(x[c.edge], x[c.edge + 1], x[o->edge], x[o->edge + 1]);
    EXPECT_NEAR(c.s, pair.s, 1e-9) << "edge " << c.edge << " against " << o->edge;
    EXPECT_NEAR(o->s, pair.t, 1e-9) << "edge " << o->edge << " against " << c.edge;
    const glm::dvec3 p = x[c.edge] + (x[c.edge + 1] - x[c.edge]) * pair.s;
    const glm::dvec3 q = x[o->edge] + (x[o->edge + 1] - x[o->edge]) * pair.t;
    if (glm::length(p - q) > 1e-6) {
      EXPECT_LT(glm::length(c.normal - glm::normalize(p - q)), 1e-9);
    }
  }
  EXPECT_EQ(paired, contacts.size());
}

}  // namespace
}  // namespace cathbox::tool

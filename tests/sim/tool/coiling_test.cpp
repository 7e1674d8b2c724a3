// Coils in an aneurysm, in virtual time: a coil released in a free sphere of the bundled sac's
// size stays in it and forms loops of its rest diameter; the packing density against the
// analytic coil volume; no loop passes into another over 10^4 random push/pull/rotate steps;
// the triaxial stack of cases/neuro_coiling.case reaches the aneurysm neck by its action file
// and deploys and detaches the coil; a second coil packs against the first in the bundled sac.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "collision/segment_pair.hpp"
#include "tool/aneurysm_sac.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "tool/coil_metrics.hpp"
#include "scenario/script_player.hpp"
#include "tool/simulator.hpp"
#include "analytic_walls.hpp"
#include "state_fnv.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {
namespace {

constexpr double kSphereR = testing::kSacSphereR, kNeckR = testing::kSacNeckR;
const glm::dvec3 kCentre = testing::kSacCentre;
constexpr double kCoilOd = 0.25;
constexpr double kLoopD = 4.0;
constexpr double kCoilLength = 40.0;

// A parent artery (radius 1 mm along z) opening into a free sphere.
TubeNetworkWall sphere_on_a_tube() { return testing::sphere_on_a_tube(kSphereR, kNeckR, kCentre); }

std::vector<ToolSpec> micro_and_coil() { return {default_microcatheter(), default_coil(kCoilLength, kLoopD)}; }

constexpr std::size_t kMicro = 0, kCoil = 1;
const Entry kEntry{{0, 0, -3}, {0, 0, 1}};
// The neck: where the sphere meets the parent tube.
const double kNeckZ = kCentre.z - std::sqrt(kSphereR * kSphereR - kNeckR * kNeckR);

void drive(Simulator& sim, std::size_t tool, double target, double per_step, CoilMetrics* metrics = nullptr) {
  while (std::abs(sim.insertion_mm(tool) - target) > 1e-9) {
    const double d = std::clamp(target - sim.insertion_mm(tool), -per_step, per_step);
    sim.set_insertion(tool, sim.insertion_mm(tool) + d);
    sim.step();
    if (metrics != nullptr) metrics->observe(sim);
  }
}

// The microcatheter's tip 1 mm into the sphere, the coil at its tip.
double place_microcatheter(Simulator& sim) {
  const double depth = kNeckZ + 1.0 - kEntry.point_mm.z;
  drive(sim, kMicro, depth, 0.2);
  drive(sim, kCoil, depth - 0.5, 0.2);
  return depth;
}

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
  ASSERT_EQ(sim.detach(kCoil), DeviceError::kNone);
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

// A coil released in the sphere and left alone comes to rest: quasi-static, with nothing moving
// it, its energy has a minimum and each step's solve only descends. Its largest node move over a
// tick from 4 to 6 s after release is under 0.1 um (1e-4 mm, 1/2500 of its 0.25 mm diameter); it
// was 8-18 um while the position solve did not see the twist's load on the centreline and the
// twist minimised another bending energy (docs/sim-tool/convergence.md).
TEST_F(CoilInSphere, ReleasedCoilLeftAloneComesToRest) {
  sim.coil_sleep_settings().enabled = false;  // solved every step (asleep it would not move at all)
  drive(sim, kCoil, micro + kCoilLength + 1.0, 0.02);
  ASSERT_EQ(sim.detach(kCoil), DeviceError::kNone);
  double worst_mm = 0.0;
  for (int i = 0; i < 6000; ++i) {
    const std::span<const glm::dvec3> x = sim.detached(0).positions();
    const std::vector<glm::dvec3> before(x.begin(), x.end());
    sim.step();
    if (i < 4000) continue;
    const std::span<const glm::dvec3> after = sim.detached(0).positions();
    for (std::size_t k = 0; k < after.size(); ++k) worst_mm = std::max(worst_mm, glm::length(after[k] - before[k]));
  }
  EXPECT_LT(worst_mm, 1e-4) << "a node moved " << 1e3 * worst_mm << " um in a tick 4-6 s after release";
  std::printf("released coil 4-6 s after release: largest node move %.5f um a tick\n", 1e3 * worst_mm);
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
  ASSERT_EQ(sim.detach(kCoil), DeviceError::kNone);
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

// The rod-rod candidate list (a Verlet list kept while the edges move less than half its skin,
// its pairs skipped while their last distance less what their ends moved since keeps them out
// of reach) gives exactly the contacts of a list built afresh at the present positions with no
// skin, for every member rod and at every step of random pushes, pulls and turns; it is not
// rebuilt at every step.
TEST_F(CoilInSphere, CandidateListGivesTheContactsOfAListBuiltAfresh) {
  drive(sim, kCoil, micro + 0.4 * kCoilLength, 0.02);
  std::mt19937 rng(7);
  // Turns most of the time: a push or pull that takes a node in or out of the simulated part
  // changes the members, which rebuilds the list anyway.
  std::uniform_real_distribution<double> push(-0.05, 0.08), turn(-0.2, 0.2);
  std::uniform_int_distribution<int> what(0, 9);
  const RodContactField& field = sim.coil_contacts();
  const std::uint64_t builds0 = field.list_builds();
  std::vector<EdgeContact> kept, fresh;
  std::size_t compared = 0;
  constexpr int kSteps = 1500;
  for (int i = 0; i < kSteps; ++i) {
    if (what(rng) == 0) {
      sim.set_insertion(kCoil, sim.insertion_mm(kCoil) + push(rng));
    } else {
      sim.set_rotation(kCoil, sim.rotation_rad(kCoil) + turn(rng));
    }
    sim.step();
    RodContactField afresh(field.margin_mm(), 0.0);
    afresh.set_members(field.members());
    for (const RodContactField::Member& m : field.members()) {
      field.gather(*m.rod, kept);
      afresh.gather(*m.rod, fresh);
      ASSERT_EQ(kept.size(), fresh.size()) << "step " << i;
      for (std::size_t c = 0; c < kept.size(); ++c) {
        ASSERT_EQ(kept[c].edge, fresh[c].edge) << "step " << i;
        ASSERT_EQ(kept[c].s, fresh[c].s) << "step " << i;
        ASSERT_EQ(kept[c].normal, fresh[c].normal) << "step " << i;
        ASSERT_EQ(kept[c].offset_mm, fresh[c].offset_mm) << "step " << i;
      }
      compared += kept.size();
    }
    const RodContactField::Overlap a = sim.worst_coil_overlap(), b = afresh.worst_overlap();
    ASSERT_EQ(a.depth_mm, b.depth_mm) << "step " << i;
  }
  // The coil touches itself: ~6 contacts a step (9,724 in all since the coil's arc predictor;
  // 10,000+ before it, with loops shrunk by the chord slide).
  EXPECT_GT(compared, 8000u);
  EXPECT_LT(field.list_builds() - builds0, static_cast<std::uint64_t>(kSteps / 2));
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

// A 150 mm coil (5 mm helical loops, the bench's) pushed whole out of the microcatheter into the
// 6.4 mm sphere at 20 mm/s, every step checked in virtual time (7,400 steps).
// Bounds, argued: the coil is a soft spring (EI 0.02 N mm^2); the force of one of its loops bent
// to the sphere is of the order EI / R^2 ~ 3 mN, and a clinician pushes coils with well under
// 1 N. The pusher force the hand feels is the 20 mN valve, the drag and these loop forces: it
// must stay below 200 mN (before the fix: 2.7e5 mN, the residual of the coil's stiff axial
// springs in an unconverged step). A wall contact of the coil may not exceed 250 mN, twice what
// the coil's penalty gives at the 5 % penetration its projection allows (before: 16-35 N, loops
// projected into the wall on stale planes); the microcatheter's (its tip pushed by the loops,
// the default penalty) 1 N. Those two are regression bounds on what the solver reaches, not
// yet the physical ~10 mN (sim/tool/README.md, Limits). Loops may not interpenetrate beyond 10 %
// of the coil diameter (issue 16; before: 11.7 %).
TEST(CoilDeploy, WholeCoilIntoTheSphereKeepsHandAndWallForcesBoundedAndLoopsApart) {
  constexpr double kLongCoil = 150.0;
  const TubeNetworkWall wall = sphere_on_a_tube();
  const std::vector<ToolSpec> tools{default_microcatheter(), default_coil(kLongCoil, 5.0)};
  Simulator sim(wall, tools, kEntry);
  const double micro = place_microcatheter(sim);
  struct Peak {
    double value = 0.0, at_mm = 0.0;
    void see(double v, double at) {
      if (v > value) value = v, at_mm = at;
    }
  };
  Peak hand, coil_wall, micro_wall, overlap;
  const double start = sim.insertion_mm(kCoil);
  while (sim.insertion_mm(kCoil) < micro + kLongCoil - 2.0) {
    sim.set_insertion(kCoil, sim.insertion_mm(kCoil) + 0.02);  // 20 mm/s at 1 kHz
    sim.step();
    const double pushed = sim.insertion_mm(kCoil) - start;
    ASSERT_TRUE(std::isfinite(sim.hand_force_mN(kCoil))) << "at " << pushed << " mm";
    hand.see(std::abs(sim.hand_force_mN(kCoil)), pushed);
    for (const RodContact& c : sim.rod(kCoil).contacts()) coil_wall.see(c.normal_force_mN, pushed);
    for (const RodContact& c : sim.rod(kMicro).contacts()) micro_wall.see(c.normal_force_mN, pushed);
    const RodContactField::Overlap o = sim.worst_coil_overlap();
    if (o.diameter_mm > 0.0) overlap.see(o.depth_mm / o.diameter_mm, pushed);
  }
  std::printf("150 mm coil: pusher %.1f mN, coil wall %.1f mN, microcatheter wall %.1f mN, overlap %.2f %%\n", hand.value,
              coil_wall.value, micro_wall.value, 100.0 * overlap.value);
  EXPECT_LT(hand.value, 200.0) << "pusher force " << hand.value << " mN at " << hand.at_mm << " mm deployed";
  EXPECT_LT(coil_wall.value, 250.0) << "coil wall contact " << coil_wall.value << " mN at " << coil_wall.at_mm << " mm";
  EXPECT_LT(micro_wall.value, 1000.0) << "microcatheter wall contact " << micro_wall.value << " mN at "
                                      << micro_wall.at_mm << " mm";
  EXPECT_LT(overlap.value, 0.10) << "loop overlap " << 100.0 * overlap.value << " % of the coil diameter at "
                                 << overlap.at_mm << " mm";
}

// The deepest loop overlap while a coil was pushed, as a fraction of the coil diameter, and how
// far it had been pushed then.
struct WorstOverlap {
  double fraction = 0.0;
  double at_mm = 0.0;
};

// Pushes `tool` to `target` mm at `per_step` mm a step, watching the coils' overlap.
WorstOverlap push_watching_overlap(Simulator& sim, std::size_t tool, double target, double per_step,
                                   CoilMetrics& metrics) {
  WorstOverlap worst;
  const double start = sim.insertion_mm(tool);
  while (sim.insertion_mm(tool) < target) {
    sim.set_insertion(tool, sim.insertion_mm(tool) + per_step);
    sim.step();
    metrics.observe(sim);
    const RodContactField::Overlap o = sim.worst_coil_overlap();
    if (o.diameter_mm > 0.0 && o.depth_mm / o.diameter_mm > worst.fraction) {
      worst = {o.depth_mm / o.diameter_mm, sim.insertion_mm(tool) - start};
    }
  }
  return worst;
}

// Two released coils packed against each other: they touch (closest nodes within a diameter
// and half a node spacing), each leaves the other room for its centre line, and the second
// passed through neither coil while it was pushed (overlap < 10 % of the coil diameter).
void expect_packed_apart(const Simulator& sim, const WorstOverlap& overlap) {
  double closest = 1e9;
  for (const glm::dvec3& a : sim.detached(0).positions()) {
    for (const glm::dvec3& b : sim.detached(1).positions()) closest = std::min(closest, glm::length(a - b));
  }
  EXPECT_LT(closest, kCoilOd + 0.25) << "the coils are " << closest << " mm apart";
  EXPECT_GT(closest, 0.5 * kCoilOd) << "the coils are " << closest << " mm apart";
  EXPECT_LT(overlap.fraction, 0.10) << "loop overlap " << 100.0 * overlap.fraction << " % of the coil diameter at "
                                    << overlap.at_mm << " mm of the second coil";
}

// Every node of every released coil on the sac's side of the neck plane (less its radius) and
// in the lumen (out by no more than 10 % of its radius).
void expect_in_the_sac(const Simulator& sim, const AneurysmSac& sac, const WallModel& wall_model) {
  const double r = 0.5 * kCoilOd;
  double shallowest = 1e9, outside = -1e9;
  for (std::size_t k = 0; k < sim.detached_count(); ++k) {
    for (const glm::dvec3& p : sim.detached(k).positions()) {
      ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
      shallowest = std::min(shallowest, sac.depth_mm(p));
      WallHint hint;
      WallContact wall;
      if (wall_model.probe(WallProbe{p, r}, hint, wall)) outside = std::max(outside, r - wall.distance_mm);
    }
  }
  EXPECT_GT(shallowest, -r) << "a coil node is " << -shallowest << " mm past the neck plane, in the M1";
  EXPECT_LT(outside, 0.1 * r) << "a coil node is out of the lumen by " << outside << " mm";
}

// Later coils pack against earlier ones: two 40 mm coils (4 mm loops) through the same
// microcatheter; the first is pushed out, detached and its pusher drawn back, then the second is
// pushed out against it. The second stays in the sphere (no node more than 10 % of its radius
// out, none herniated) and passes through neither the first nor itself (overlap < 10 % of the
// coil diameter at every step).
TEST(CoilDeploy, SecondCoilPacksAgainstTheFirstDetachedOneAndStaysInTheSac) {
  const TubeNetworkWall wall = sphere_on_a_tube();
  ToolSpec first = default_coil(kCoilLength, kLoopD), second = default_coil(kCoilLength, kLoopD);
  first.name = "coil 1";
  second.name = "coil 2";
  const std::vector<ToolSpec> tools{default_microcatheter(), first, second};
  constexpr std::size_t kFirst = 1, kSecond = 2;
  Simulator sim(wall, tools, kEntry);
  const double micro = kNeckZ + 1.0 - kEntry.point_mm.z;
  drive(sim, kMicro, micro, 0.2);
  drive(sim, kFirst, micro - 0.5, 0.2);
  drive(sim, kSecond, micro - 20.0, 0.2);
  const AneurysmSac sac = *sphere_cap_sac(kCentre, kSphereR, {0, 0, kNeckZ});
  CoilMetrics metrics(sim, sac);
  drive(sim, kFirst, micro + kCoilLength + 1.0, 0.02, &metrics);
  ASSERT_EQ(sim.detach(kFirst), DeviceError::kNone);
  drive(sim, kFirst, micro - 10.0, 0.2, &metrics);  // the pusher back, its end 10 mm inside the tip
  drive(sim, kSecond, micro - 0.5, 0.2, &metrics);
  const WorstOverlap overlap = push_watching_overlap(sim, kSecond, micro + kCoilLength + 1.0, 0.02, metrics);
  ASSERT_EQ(sim.detach(kSecond), DeviceError::kNone);
  for (int i = 0; i < 200; ++i) {
    sim.step();
    metrics.observe(sim);
  }
  ASSERT_EQ(sim.detached_count(), 2u);
  double worst = -1e9;
  for (std::size_t c = 0; c < 2; ++c) {
    for (const glm::dvec3& p : sim.detached(c).positions()) {
      ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
      worst = std::max(worst, glm::length(p - kCentre) + 0.5 * kCoilOd - kSphereR);
    }
  }
  EXPECT_LT(worst, 0.1 * 0.5 * kCoilOd) << "a node is " << worst << " mm outside the sphere";
  EXPECT_EQ(metrics.figures().herniations, 0);
  EXPECT_NEAR(metrics.figures().deployed_mm, 2.0 * kCoilLength, 0.6);
  expect_packed_apart(sim, overlap);
}

// The triaxial stack of the bundled coiling case, driven by its action file as `cathbox sim
// run` drives it: from the guide in the right ICA the microcatheter reaches the neck of the
// right MCA aneurysm over the microwire, the framing coil deploys into the sac and is detached
// there; `load_coil` then feeds the case's next coil (40 mm, 4 mm loops) into the same
// microcatheter on a new pusher, and it packs against the first: every node of both in the sac
// (none past the neck plane, none out of the lumen by more than 10 % of its radius), no
// herniation, the coils touching without crossing, overlap <= 10 % of the coil diameter at
// every step of the second coil, the packing density the sum of both coils' volumes.
TEST(Coiling, TriaxialStackReachesTheAneurysmNeckByTheScriptedActionFile) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  CaseParse c = load_case(dir + "neuro_coiling.case");
  ASSERT_TRUE(c) << c.error().message;
  ScriptParse script = load_script(dir + "neuro_coiling.actions");
  ASSERT_TRUE(script) << script.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  ASSERT_TRUE((*world)->sac());
  const AneurysmSac& sac = *(*world)->sac();
  // The right side (the patient's right is -x): the sac, the case's target and the entry.
  const vessel::VesselModel& model = *(*world)->model();
  EXPECT_EQ(model.segments[*model.index_of(sac.segment)].name, "right_mca_aneurysm");
  ASSERT_TRUE(c->target);
  EXPECT_EQ(c->target->segment, sac.segment);
  EXPECT_LT(sac.neck_centre_mm.x, -25.0);
  EXPECT_LT((*world)->entry().point_mm.x, -20.0);
  Simulator sim((*world)->wall(), c->tools, (*world)->entry());
  const std::size_t micro = sim.find_tool("microcatheter"), coil = sim.find_tool("coil");
  ASSERT_LT(micro, sim.tool_count());
  ASSERT_LT(coil, sim.tool_count());
  ASSERT_EQ(sim.outer_of(micro), sim.find_tool("guide"));
  ASSERT_EQ(sim.outer_of(sim.find_tool("microwire")), micro);
  ASSERT_EQ(sim.outer_of(coil), micro);
  EXPECT_EQ(c->tools[coil].sections.back().shape, CoilShape::kHelix);
  EXPECT_EQ(c->tools[coil].sections.back().loop_diameter_mm, 5.0);
  ASSERT_EQ(c->tools[coil].next_coils.size(), 1u);
  const double second_mm = c->tools[coil].next_coils[0].length_mm;
  std::vector<ScriptPlayer::ToolInfo> infos;
  for (const ToolSpec& t : c->tools) infos.push_back(tool_info(t));
  base::Result<ScriptPlayer> player = ScriptPlayer::make(*script, infos, 0, "neuro_coiling.actions");
  ASSERT_TRUE(player) << player.error().message;
  CoilMetrics metrics(sim, sac);
  double micro_best_depth = -1e9;
  std::optional<double> depth_at_deploy;
  bool detached = false;
  WorstOverlap second_overlap;  // while the second coil is out
  double pusher_peak_mN = 0.0;  // the coil tool's hand force after a detach, pusher alone
  for (std::int64_t now = 0; now < 200'000; ++now) {
    const ScriptPlayer::Step step = player->advance(now);
    if (step.selected) sim.select(*step.selected);
    if (step.ended) break;
    if (step.detach) {
      ASSERT_EQ(sim.detach(*step.detach), DeviceError::kNone) << "at " << now << " ms";
      detached = true;
    }
    if (step.load_coil) {
      ASSERT_EQ(sim.load_next_coil(*step.load_coil), DeviceError::kNone) << "at " << now << " ms";
    }
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      sim.set_insertion(t, player->insertion_mm(t));
      sim.set_rotation(t, player->rotation_rad(t));
    }
    sim.step();
    metrics.observe(sim);
    if (sim.released_mm(coil) > 0.0) pusher_peak_mN = std::max(pusher_peak_mN, std::abs(sim.hand_force_mN(coil)));
    const glm::dvec3 tip = sim.tip(micro).position_mm;
    if (glm::length(tip - sac.neck_centre_mm) < sac.neck_radius_mm + sac.dome_radius_mm) {
      micro_best_depth = std::max(micro_best_depth, sac.depth_mm(tip));
    }
    if (!depth_at_deploy && metrics.figures().deployed_mm > 0.0) depth_at_deploy = sac.depth_mm(tip);
    if (sim.coils_loaded(coil) == 1) {
      const RodContactField::Overlap o = sim.worst_coil_overlap();
      if (o.diameter_mm > 0.0 && o.depth_mm / o.diameter_mm > second_overlap.fraction) {
        second_overlap = {o.depth_mm / o.diameter_mm, metrics.figures().deployed_mm - c->tools[coil].detach_mm};
      }
    }
    if (player->settled(now, 100)) break;
  }
  // The microcatheter's tip came to the neck (within half a millimetre of its plane, or past it).
  EXPECT_GT(micro_best_depth, -0.5) << "closest approach to the neck plane " << micro_best_depth << " mm";
  ASSERT_TRUE(depth_at_deploy);
  EXPECT_GT(*depth_at_deploy, -0.5);
  EXPECT_TRUE(detached);
  EXPECT_EQ(sim.coils_loaded(coil), 1u);
  ASSERT_EQ(sim.detached_count(), 2u);
  const double total = c->tools[coil].detach_mm + second_mm;
  EXPECT_NEAR(metrics.figures().deployed_mm, total, 0.6);
  // Packing density: the sum of both coils' analytic volumes over the sac.
  EXPECT_NEAR(metrics.figures().packing_density, 0.25 * std::acos(-1.0) * kCoilOd * kCoilOd * total / sac.volume_mm3, 1e-3);
  EXPECT_EQ(metrics.figures().herniations, 0);
  EXPECT_LT(metrics.figures().kick_back_mm, 2.0);
  expect_in_the_sac(sim, sac, (*world)->wall());
  expect_packed_apart(sim, second_overlap);
  // After a detach the pusher alone (the coil's stiff axial springs, out of the rod-contact
  // field) reads its hand force at the linearised equilibrium: 1 um of residual read as
  // 3·10^5-1.6·10^6 mN before; 17-31 N while the script pushed the detachment zone 1.5 mm out
  // of a microcatheter tip lying on the sac wall (1.17 N at 0.1 mm, drawn back): the bound
  // catches the reading, not that.
  EXPECT_LT(pusher_peak_mN, 5.0e4);
  std::printf("pusher after detach: peak %.0f mN\n", pusher_peak_mN);
  std::printf("two coils: %.1f mm deployed, packing %.2f %% of %.1f mm3, %d herniations, kick-back %.2f mm, "
              "second coil's deepest overlap %.1f %% of the diameter\n",
              metrics.figures().deployed_mm, 100.0 * metrics.figures().packing_density, sac.volume_mm3,
              metrics.figures().herniations, metrics.figures().kick_back_mm, 100.0 * second_overlap.fraction);
  // The end state, bit for bit: the same build gives the same hash alone or beside any load.
  std::printf("end-state hash %016llx after %llu steps\n", static_cast<unsigned long long>(testing::state_fnv(sim)),
              static_cast<unsigned long long>(sim.steps()));
}

// Later coils pack against earlier ones in the bundled sac (the bundled coiling case holds 4
// tools, its triaxial stack and one coil, so this runs beside it): the microcatheter parked in
// the right M1 with its tip ~2 mm past the neck of right_mca_aneurysm, a 60 mm framing coil (5 mm
// loops) pushed out at 8 mm/s and detached, its pusher drawn back, then a 40 mm filling coil (4
// mm loops) pushed out against it and detached. Every node of both stays in the sac (none past
// the neck plane into the M1, none out of the lumen by more than 10 % of its radius), no
// herniation; the second touches the first without passing through it or itself.
TEST(Coiling, SecondCoilPacksAgainstTheFirstInTheBundledSac) {
  constexpr std::string_view kCase = R"(cathbox-case 1
name two coils in the right MCA aneurysm, microcatheter parked in the M1
vessel neuro_aneurysm.hclm
entry -19.09 15.71 236.58  -0.981 0.038 0.189
tool microcatheter catheter
  section 1500 od=0.7 ei=1 gj=0.8
  friction 0.1
  inner_diameter 0.43
  spacing 2 0.5 40
end
)";
  // A 10-system coil on its pusher (as in cases/neuro_coiling.case), LENGTH mm of LOOP mm loops.
  const auto coil = [](const std::string& name, int length, int loop) {
    return "tool " + name + " coil\n  section 1800 od=0.33 ei=10 gj=8\n  section " + std::to_string(length) +
           " od=0.25 ei=0.02 gj=0.016 shape=helix loop=" + std::to_string(loop) + "\n  friction 0.05\n  detach " +
           std::to_string(length) + "\n  inside microcatheter\n  spacing 2 0.5 " + std::to_string(length + 2) + "\nend\n";
  };
  CaseParse c = parse_case(std::string(kCase) + coil("coil", 60, 5) + coil("coil2", 40, 4),
                           std::string(CATHBOX_SOURCE_DIR) + "/cases/two_coils.case");
  ASSERT_TRUE(c) << c.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  ASSERT_TRUE((*world)->sac());
  const AneurysmSac& sac = *(*world)->sac();
  Simulator sim((*world)->wall(), c->tools, (*world)->entry());
  constexpr std::size_t kMicroTool = 0, kFirst = 1, kSecond = 2;
  constexpr double kTip = 14.0;  // the microcatheter's tip ~1.8 mm past the neck
  drive(sim, kMicroTool, kTip, 0.01);
  ASSERT_GT(sac.depth_mm(sim.tip(kMicroTool).position_mm), 0.5);
  drive(sim, kFirst, kTip - 4.0, 0.01);
  drive(sim, kSecond, kTip - 9.0, 0.01);
  CoilMetrics metrics(sim, sac);
  drive(sim, kFirst, kTip + 61.5, 0.008, &metrics);  // 8 mm/s until the detachment zone is out
  ASSERT_EQ(sim.detach(kFirst), DeviceError::kNone);
  drive(sim, kFirst, 0.0, 0.04, &metrics);
  drive(sim, kSecond, kTip - 4.0, 0.01, &metrics);
  const WorstOverlap overlap = push_watching_overlap(sim, kSecond, kTip + 41.5, 0.008, metrics);
  ASSERT_EQ(sim.detach(kSecond), DeviceError::kNone);
  drive(sim, kSecond, 0.0, 0.04, &metrics);
  ASSERT_EQ(sim.detached_count(), 2u);
  expect_in_the_sac(sim, sac, (*world)->wall());
  EXPECT_EQ(metrics.figures().herniations, 0);
  EXPECT_LT(metrics.figures().kick_back_mm, 2.0);
  EXPECT_NEAR(metrics.figures().deployed_mm, 100.0, 0.6);
  EXPECT_NEAR(metrics.figures().packing_density, 0.25 * std::acos(-1.0) * kCoilOd * kCoilOd * 100.0 / sac.volume_mm3, 1e-3);
  expect_packed_apart(sim, overlap);
}

// cases/neuro_coiling_dense.*: four coils (230 mm) through one microcatheter into the small round sac
// of neuro_small_aneurysm.hclm, each loaded only after the last was detached, each pushed out
// until its detachment zone is 0.1 mm past the tip (the script's markers, the microcatheter
// pushed to 152.5 mm: 152.6 mm + the coil's length), framing first (its loops 3.5 mm in the
// 3.94 mm dome), then loops of non-increasing size.
TEST(Coiling, DenseSequenceDetachesEachCoilBeforeTheNextAndPushesEachToItsMarkers) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  CaseParse c = load_case(dir + "neuro_coiling_dense.case");
  ASSERT_TRUE(c) << c.error().message;
  ScriptParse script = load_script(dir + "neuro_coiling_dense.actions");
  ASSERT_TRUE(script) << script.error().message;
  const auto coil = std::find_if(c->tools.begin(), c->tools.end(), [](const ToolSpec& t) { return t.kind == ToolKind::kCoil; });
  ASSERT_NE(coil, c->tools.end());
  std::vector<const ToolSection*> coils{&coil->sections.back()};
  for (const ToolSection& s : coil->next_coils) coils.push_back(&s);
  ASSERT_EQ(coils.size(), 4u);
  EXPECT_EQ(coils.front()->loop_diameter_mm, 3.5);
  double total = 0.0;
  for (std::size_t k = 0; k < coils.size(); ++k) {
    total += coils[k]->length_mm;
    if (k > 0) {
      EXPECT_LE(coils[k]->loop_diameter_mm, coils[k - 1]->loop_diameter_mm) << "coil " << k + 1;
    }
  }
  EXPECT_NEAR(total, 230.0, 1e-9);
  std::size_t loaded = 0, detached = 0;
  bool attached = true;
  for (const Action& a : script->actions) {
    if (a.kind == ActionKind::kDetach) {
      EXPECT_TRUE(attached) << "line " << a.line << ": detach with no coil attached";
      attached = false, ++detached;
    } else if (a.kind == ActionKind::kLoadCoil) {
      EXPECT_FALSE(attached) << "line " << a.line << ": load_coil before the last coil was detached";
      attached = true, ++loaded;
    } else if (a.kind == ActionKind::kInsertTo && a.speed == 8.0 && loaded < coils.size()) {
      EXPECT_NEAR(a.value, 152.6 + coils[loaded]->length_mm, 1e-9) << "line " << a.line;
    }
  }
  EXPECT_EQ(loaded, 3u);
  EXPECT_EQ(detached, 4u);
}

}  // namespace
}  // namespace cathbox::tool

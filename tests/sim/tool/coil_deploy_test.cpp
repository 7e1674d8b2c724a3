// Coils pushed whole into the free sphere, in virtual time: a 150 mm coil keeps hand and wall
// forces bounded and its loops apart; a second coil packs against the first, detached one and
// stays in the sac.
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "tool/aneurysm_sac.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/simulator.hpp"

#include "coil_test_support.hpp"

namespace cathbox::tool {
namespace {

using namespace testing;  // coil_test_support.hpp: the sphere, the tools, drive and the packing checks

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
// of the coil diameter (issue 16; before: 11.7 %). Under 1 % of the steps may end unconverged
// (issue 29; 8.1 % before the stretch correction and the join rounds, convergence.md).
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
  int steps = 0, unconverged = 0;
  const double start = sim.insertion_mm(kCoil);
  while (sim.insertion_mm(kCoil) < micro + kLongCoil - 2.0) {
    sim.set_insertion(kCoil, sim.insertion_mm(kCoil) + 0.02);  // 20 mm/s at 1 kHz
    sim.step();
    ++steps;
    unconverged += sim.rod(kCoil).converged() ? 0 : 1;
    const double pushed = sim.insertion_mm(kCoil) - start;
    ASSERT_TRUE(std::isfinite(sim.hand_force_mN(kCoil))) << "at " << pushed << " mm";
    hand.see(std::abs(sim.hand_force_mN(kCoil)), pushed);
    for (const RodContact& c : sim.rod(kCoil).contacts()) coil_wall.see(c.normal_force_mN, pushed);
    for (const RodContact& c : sim.rod(kMicro).contacts()) micro_wall.see(c.normal_force_mN, pushed);
    const RodContactField::Overlap o = sim.worst_coil_overlap();
    if (o.diameter_mm > 0.0) overlap.see(o.depth_mm / o.diameter_mm, pushed);
  }
  const double unconverged_pct = 100.0 * unconverged / steps;
  std::printf("150 mm coil: pusher %.1f mN, coil wall %.1f mN, microcatheter wall %.1f mN, overlap %.2f %%, unconverged %.2f %%\n",
              hand.value, coil_wall.value, micro_wall.value, 100.0 * overlap.value, unconverged_pct);
  EXPECT_LT(hand.value, 200.0) << "pusher force " << hand.value << " mN at " << hand.at_mm << " mm deployed";
  EXPECT_LT(coil_wall.value, 250.0) << "coil wall contact " << coil_wall.value << " mN at " << coil_wall.at_mm << " mm";
  EXPECT_LT(micro_wall.value, 1000.0) << "microcatheter wall contact " << micro_wall.value << " mN at "
                                      << micro_wall.at_mm << " mm";
  EXPECT_LT(overlap.value, 0.10) << "loop overlap " << 100.0 * overlap.value << " % of the coil diameter at "
                                 << overlap.at_mm << " mm";
  EXPECT_LT(unconverged_pct, 1.0) << unconverged << " of " << steps << " steps unconverged";
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
  ASSERT_EQ(release_coil(sim, kFirst, &metrics), DeviceError::kNone);
  drive(sim, kFirst, micro - 10.0, 0.2, &metrics);  // the pusher back, its end 10 mm inside the tip
  drive(sim, kSecond, micro - 0.5, 0.2, &metrics);
  const WorstOverlap overlap = push_watching_overlap(sim, kSecond, micro + kCoilLength + 1.0, 0.02, metrics);
  ASSERT_EQ(release_coil(sim, kSecond, &metrics), DeviceError::kNone);
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

}  // namespace
}  // namespace cathbox::tool

// The herniation detector (tool::CoilMetrics) on constructed cases, against the clinical
// definition it follows: a coil or a loop of coil protruding from the sac into the parent
// artery's lumen, whatever its extent (Abdihalim et al., AJNR 32(8):1392, 2011: grade I a loop
// or coil in the parent lumen less than half the parent artery's diameter, grades II and III
// beyond). Nodes wholly past the neck plane on the parent's side count, and the extent (how many,
// how deep) is reported beside the episodes.
//   - a coil deployed in a free sphere on a parent tube: nothing counts;
//   - the same coil, still attached, dragged with its microcatheter back through the neck (the
//     catheter's tip 7 mm into the parent artery): its loops in the parent artery count, at least
//     the length between the tip and the neck less the leaving zone, as one episode, and the
//     deepest protrusion is at least the tip's depth less the leaving zone (and a node spacing).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "scenario/case_file.hpp"
#include "tool/aneurysm_sac.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {
namespace {

constexpr double kSphereR = testing::kSacSphereR, kNeckR = testing::kSacNeckR;
const glm::dvec3 kCentre = testing::kSacCentre;
const Entry kEntry{{0, 0, -3}, {0, 0, 1}};
const double kNeckZ = kCentre.z - std::sqrt(kSphereR * kSphereR - kNeckR * kNeckR);
constexpr std::size_t kMicro = 0, kCoil = 1;
constexpr double kCoilLength = 40.0, kLoopD = 4.0;

// Moves the listed tools together by `per_step` a step, `steps` steps, watching the sac.
void move_together(Simulator& sim, const std::vector<std::size_t>& tools, double per_step, int steps, CoilMetrics& m) {
  for (int i = 0; i < steps; ++i) {
    for (const std::size_t t : tools) sim.set_insertion(t, sim.insertion_mm(t) + per_step);
    sim.step();
    m.observe(sim);
  }
}

TEST(CoilHerniation, ACoilLoopDraggedIntoTheParentArteryCountsAndACoilInTheSacDoesNot) {
  const TubeNetworkWall wall = testing::sphere_on_a_tube(kSphereR, kNeckR, kCentre);
  const std::vector<ToolSpec> tools{default_microcatheter(), default_coil(kCoilLength, kLoopD)};
  Simulator sim(wall, tools, kEntry);
  const AneurysmSac sac = *sphere_cap_sac(kCentre, kSphereR, {0, 0, kNeckZ});
  CoilMetrics m(sim, sac);
  // The microcatheter's tip 1 mm into the sphere, the coil at its tip, then 20 mm of coil out at
  // 20 mm/s: loops in the sac only.
  const double tip = kNeckZ + 1.0 - kEntry.point_mm.z;
  move_together(sim, {kMicro}, 0.2, static_cast<int>(std::lround(tip / 0.2)), m);
  move_together(sim, {kCoil}, 0.2, static_cast<int>(std::lround((tip - 0.5) / 0.2)), m);
  move_together(sim, {kCoil}, 0.02, 1025, m);
  ASSERT_GT(m.figures().deployed_mm, 19.0);
  EXPECT_EQ(m.figures().herniated_nodes, 0);
  EXPECT_EQ(m.figures().herniations, 0);
  EXPECT_EQ(m.figures().herniated_depth_mm, 0.0);

  // Catheter and pusher drawn back together 8 mm at 20 mm/s: the tip 7 mm below the neck plane,
  // the coil it drags through the neck lies in the parent artery from the neck to the tip.
  constexpr double kBack_mm = 8.0;
  move_together(sim, {kMicro, kCoil}, -0.02, static_cast<int>(std::lround(kBack_mm / 0.02)), m);
  for (int i = 0; i < 200; ++i) {  // 0.2 s held
    sim.step();
    m.observe(sim);
  }
  const double tip_below_mm = -sac.depth_mm(sim.tip(kMicro).position_mm);
  ASSERT_GT(tip_below_mm, 5.0) << "the catheter's tip is not in the parent artery";
  const Rod& coil = sim.rod(kCoil);
  const double spacing = coil.node_from_tip_mm(coil.node_total() - 2) - coil.node_from_tip_mm(coil.node_total() - 1);
  const double in_parent_mm = tip_below_mm - CoilMetrics::kLeavingZone_mm - coil.node_radius_mm(coil.node_total() - 1);
  std::printf("tip %.2f mm below the neck: %d nodes herniated (%.2f mm apart), deepest %.2f mm, %d episode(s)\n",
              tip_below_mm, m.figures().herniated_nodes, spacing, m.figures().herniated_depth_mm, m.figures().herniations);
  EXPECT_GE(m.figures().herniated_nodes * std::abs(spacing), in_parent_mm - std::abs(spacing));
  EXPECT_EQ(m.figures().herniations, 1);
  EXPECT_GE(m.figures().herniated_depth_mm, in_parent_mm - std::abs(spacing));
}

}  // namespace
}  // namespace cathbox::tool

// The steered microwire of the triaxial stack (nested_tool_setup.hpp) in the analytic Y: which
// shape is right when its solve converges (issue 29, item 2; docs/sim-tool/convergence.md, "The
// steered wire's fold is an edge through the carina").
//
// With every tick converged (30 Newton iterations) the wire, turned half a turn into the left
// branch and pushed at 0.2 mm a step, folds back at 55 mm: its tip retreats from z 6.9 to 3.4 mm.
// It is held on the flow divider: two nodes 0.5 mm apart, one in each child, each pressed on its
// own child's wall (normals (+-0.94, 0, 0.33): both faces of the divider's apex) and the edge
// between them passes through the apex. The divider is a convex wedge; a wire on the lumen's
// side of it touches at most one face at a point and slides off it frictionlessly unless its
// push is exactly along that face's normal, so a frictionless wire cannot be caught there; only
// a wire through the wedge can (geometry of the analytic Y: the apex lies where a child's wall
// meets the plane x = 0, 0.330 z = 2 - 0.4 * 0.943 z / 42.4, z = 5.90 mm). The held shape is
// the node-only contact's artefact, not an equilibrium of the rod in the lumen: the right shape
// keeps every part of the wire in the lumen (within the README's 10 % of its radius) and, the
// wire being frictionless, advances its tip into the branch. It needs the wall against the
// edges (RodSettings::edge_wall_contact, rod_edge_wall.cpp; off by default): with node contacts
// alone the edge between the two held nodes passes through the apex.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "nested_tool_setup.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {
namespace {

// Distance from `p` to the wall of the union of frusta, positive inside (the largest over the
// tubes of the radius at p's station less p's distance from the axis).
double clearance_in(const std::vector<Tube>& tubes, const glm::dvec3& p) {
  double best = -1e9;
  for (const Tube& t : tubes) {
    const glm::dvec3 axis = t.b_mm - t.a_mm;
    const double s = std::clamp(glm::dot(p - t.a_mm, axis) / glm::dot(axis, axis), 0.0, 1.0);
    const double r = t.radius_a_mm + s * (t.radius_b_mm - t.radius_a_mm);
    best = std::max(best, r - glm::length(p - (t.a_mm + s * axis)));
  }
  return best;
}

TEST(SteeredWire, ConvergedItStaysInTheLumenAtTheCarinaAndAdvancesIntoTheBranch) {
  const std::vector<Tube> tubes{Tube{{0, 0, -45}, {0, 0, 0}, 2.0, 2.0, 0}, Tube{{0, 0, 0}, {14, 0, 40}, 2.0, 1.6, 1},
                                Tube{{0, 0, 0}, {-14, 0, 40}, 2.0, 1.6, 2}};
  const TubeNetworkWall wall(tubes);
  RodSettings converged;
  converged.newton_iterations = 30;
  converged.edge_wall_contact = true;
  Simulator sim(wall, testing::triaxial_stack(), testing::kTriaxialEntry, converged);
  testing::steer_wire_into_a_branch(sim, 0.5, 41.0);
  double deepest = 0.0;  // edge midpoints of the wire's distal 20 mm past the wall, in radii
  double furthest = -1e9;
  int unconverged = 0;
  while (sim.insertion_mm(2) < 70.0 - 1e-9) {
    sim.set_insertion(2, std::min(70.0, sim.insertion_mm(2) + 0.2));
    sim.step();
    const Rod& rod = sim.rod(2);
    unconverged += rod.converged() ? 0 : 1;
    const auto x = rod.positions();
    for (std::size_t k = rod.first_free_node(); k + 1 < x.size(); ++k) {
      if (rod.node_from_tip_mm(k) > 20.0) continue;
      const double r = rod.node_radius_mm(k);
      deepest = std::max(deepest, (r - clearance_in(tubes, 0.5 * (x[k] + x[k + 1]))) / r);
    }
    furthest = std::max(furthest, sim.tip(2).position_mm.z);
  }
  std::printf("steered wire at the carina: %d unconverged, edge midpoints %.3f radii past the wall at most, tip z %.2f mm "
              "(furthest %.2f) in segment %d\n",
              unconverged, deepest, sim.tip(2).position_mm.z, furthest, sim.tip_segment(2));
  EXPECT_EQ(unconverged, 0);
  // Edge midpoints' penetration, in radii of the wire (measured: 1.3 at the fold: the centreline 0.05 mm inside the apex).
  EXPECT_LT(deepest, 0.1);
  // Not folded: the tip within 3 mm of its furthest point (measured: 3.5 mm back) in a branch.
  EXPECT_NE(sim.tip_segment(2), 0);
  EXPECT_GT(sim.tip(2).position_mm.z, furthest - 3.0);
}

}  // namespace
}  // namespace cathbox::tool

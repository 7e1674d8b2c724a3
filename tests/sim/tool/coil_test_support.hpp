#pragma once
// What the coil tests share (coil_in_sphere_test.cpp, coil_deploy_test.cpp, coiling_test.cpp):
// the bundled sac's free sphere on a parent tube, a microcatheter and a 40 mm coil in it, driving
// a tool in steps, and the checks that released coils pack apart and stay in the sac.
#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "coil_release.hpp"
#include "scenario/case_file.hpp"
#include "tool/aneurysm_sac.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool::testing {

inline constexpr double kSphereR = testing::kSacSphereR, kNeckR = testing::kSacNeckR;
inline const glm::dvec3 kCentre = testing::kSacCentre;
inline constexpr double kCoilOd = 0.25;
inline constexpr double kLoopD = 4.0;
inline constexpr double kCoilLength = 40.0;

// A parent artery (radius 1 mm along z) opening into a free sphere.
inline TubeNetworkWall sphere_on_a_tube() { return testing::sphere_on_a_tube(kSphereR, kNeckR, kCentre); }

inline std::vector<ToolSpec> micro_and_coil() { return {default_microcatheter(), default_coil(kCoilLength, kLoopD)}; }

inline constexpr std::size_t kMicro = 0, kCoil = 1;
inline const Entry kEntry{{0, 0, -3}, {0, 0, 1}};
// The neck: where the sphere meets the parent tube.
inline const double kNeckZ = kCentre.z - std::sqrt(kSphereR * kSphereR - kNeckR * kNeckR);

inline void drive(Simulator& sim, std::size_t tool, double target, double per_step, CoilMetrics* metrics = nullptr) {
  while (std::abs(sim.insertion_mm(tool) - target) > 1e-9) {
    const double d = std::clamp(target - sim.insertion_mm(tool), -per_step, per_step);
    sim.set_insertion(tool, sim.insertion_mm(tool) + d);
    sim.step();
    if (metrics != nullptr) metrics->observe(sim);
  }
}

// The microcatheter's tip 1 mm into the sphere, the coil at its tip.
inline double place_microcatheter(Simulator& sim) {
  const double depth = kNeckZ + 1.0 - kEntry.point_mm.z;
  drive(sim, kMicro, depth, 0.2);
  drive(sim, kCoil, depth - 0.5, 0.2);
  return depth;
}

// The deepest loop overlap while a coil was pushed, as a fraction of the coil diameter, and how
// far it had been pushed then; and the closest its free nodes came to the first released coil.
struct WorstOverlap {
  double fraction = 0.0;
  double at_mm = 0.0;
  double closest_mm = 1e9;
};

// The closest node of `tool`'s free part to the first released coil (none released: 1e9).
inline double closest_to_first_released(const Simulator& sim, std::size_t tool) {
  double closest = 1e9;
  if (sim.detached_count() == 0) return closest;
  const Rod& rod = sim.rod(tool);
  const std::span<const glm::dvec3> free = rod.positions().subspan(std::min(rod.first_free_node(), rod.node_total()));
  for (const glm::dvec3& a : sim.detached(0).positions()) {
    for (const glm::dvec3& b : free) closest = std::min(closest, glm::length(a - b));
  }
  return closest;
}

// Pushes `tool` to `target` mm at `per_step` mm a step, watching the coils' overlap.
inline WorstOverlap push_watching_overlap(Simulator& sim, std::size_t tool, double target, double per_step,
                                          CoilMetrics& metrics) {
  WorstOverlap worst;
  const double start = sim.insertion_mm(tool);
  while (sim.insertion_mm(tool) < target) {
    sim.set_insertion(tool, sim.insertion_mm(tool) + per_step);
    sim.step();
    metrics.observe(sim);
    const RodContactField::Overlap o = sim.worst_coil_overlap();
    if (o.diameter_mm > 0.0 && o.depth_mm / o.diameter_mm > worst.fraction) {
      worst.fraction = o.depth_mm / o.diameter_mm;
      worst.at_mm = sim.insertion_mm(tool) - start;
    }
    worst.closest_mm = std::min(worst.closest_mm, closest_to_first_released(sim, tool));
  }
  return worst;
}

// Two released coils packed against each other: the second was pressed on the first (their
// closest nodes within a diameter and half a node spacing while it was pushed, or at rest: a
// released coil still drifts a few tenths of a millimetre, docs/sim-tool/convergence.md,
// "Released coils do not come to rest"), each leaves the other room for its centre line, and
// the second passed through neither coil while it was pushed (overlap < 10 % of the diameter).
inline void expect_packed_apart(const Simulator& sim, const WorstOverlap& overlap) {
  double closest = 1e9;
  for (const glm::dvec3& a : sim.detached(0).positions()) {
    for (const glm::dvec3& b : sim.detached(1).positions()) closest = std::min(closest, glm::length(a - b));
  }
  EXPECT_LT(std::min(closest, overlap.closest_mm), kCoilOd + 0.25)
      << "the coils came no closer than " << overlap.closest_mm << " mm while the second was pushed, and are " << closest
      << " mm apart";
  EXPECT_GT(closest, 0.5 * kCoilOd) << "the coils are " << closest << " mm apart";
  EXPECT_LT(overlap.fraction, 0.10) << "loop overlap " << 100.0 * overlap.fraction << " % of the coil diameter at "
                                    << overlap.at_mm << " mm of the second coil";
}

// Every node of every released coil on the sac's side of the neck plane (less its radius) and
// in the lumen (out by no more than 10 % of its radius).
inline void expect_in_the_sac(const Simulator& sim, const AneurysmSac& sac, const WallModel& wall_model) {
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

}  // namespace cathbox::tool::testing

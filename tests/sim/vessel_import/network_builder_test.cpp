#include "vessel_import/network_builder.hpp"

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::vessel_import {
namespace {

using vessel::CenterlinePoint;

// Points from a to b every `spacing` mm, radius r.
std::vector<CenterlinePoint> straight(const glm::dvec3& a, const glm::dvec3& b, double r, double spacing = 0.5) {
  const int n = std::max(1, static_cast<int>(std::round(glm::length(b - a) / spacing)));
  std::vector<CenterlinePoint> out;
  for (int i = 0; i <= n; ++i) out.push_back({a + (b - a) * (static_cast<double>(i) / n), r});
  return out;
}

std::vector<CenterlinePoint> joined(std::vector<CenterlinePoint> a, const std::vector<CenterlinePoint>& b) {
  a.insert(a.end(), b.begin() + 1, b.end());
  return a;
}

Polyline line(std::vector<CenterlinePoint> points, std::string name = {}) { return {std::move(points), std::move(name), {}}; }

// The model must be valid HCLM, mesh to a closed manifold, and have the expected shape.
void expect_network(const NetworkBuild& built, std::size_t segments, std::size_t junctions, std::size_t cycles) {
  ASSERT_TRUE(built.ok()) << built.error;
  EXPECT_TRUE(vessel::validate_model(built.model).empty()) << vessel::validate_model(built.model).front().to_string();
  EXPECT_EQ(built.model.segments.size(), segments);
  EXPECT_EQ(built.stats.junctions, junctions);
  EXPECT_EQ(built.stats.cycles, cycles);
  const vessel::VesselGraph graph(built.model);
  EXPECT_EQ(graph.junctions().size(), junctions);
  EXPECT_EQ(static_cast<std::size_t>(graph.cycle_count()), cycles);
  const vessel::VesselSurface surface = vessel::build_vessel_surface(built.model);
  ASSERT_TRUE(surface.ok()) << surface.error;
  EXPECT_EQ(surface.euler_characteristic, 2 * graph.component_count() - 2 * graph.cycle_count());
}

TEST(NetworkBuilder, OverlappingCentrelinesShareOneTrunk) {
  // Three VMTK-style centrelines from one inlet: the trunk repeated point for point (the third
  // with 0.05 mm of jitter), then each to its own outlet; the third also shares the second's
  // first 10 mm. Expected: trunk, branch 1, branch 2 up to the split, the rest of branch 2, the
  // third's own part: 5 segments, 2 junctions.
  const auto trunk = straight({0, 0, 0}, {0, 0, 40}, 3.0);
  const auto b1 = straight({0, 0, 40}, {15, 0, 70}, 2.0);
  const auto b2a = straight({0, 0, 40}, {-6, 0, 52}, 2.2);
  const auto b2b = straight({-6, 0, 52}, {-20, 0, 75}, 1.8);
  const auto b3 = straight({-6, 0, 52}, {-4, 15, 70}, 1.5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  auto third = joined(joined(trunk, b2a), b3);
  for (std::size_t i = 0; i < trunk.size() + b2a.size() - 2; ++i) third[i].pos_mm += glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
  const NetworkBuild built = build_network(std::vector<Polyline>{line(joined(trunk, b1), "to 1"),
                                                                 line(joined(joined(trunk, b2a), b2b), "to 2"),
                                                                 line(third, "to 3")});
  expect_network(built, 5, 2, 0);
  EXPECT_EQ(built.stats.overlapping, 2u);
  EXPECT_GT(built.stats.shared_points, trunk.size() * 2 - 4);
  // The junctions are where the branches part (within a radius of it).
  const vessel::VesselGraph graph(built.model);
  std::vector<glm::dvec3> expected = {{0, 0, 40}, {-6, 0, 52}};
  for (const glm::dvec3& e : expected) {
    double best = 1e9;
    for (const vessel::Junction& j : graph.junctions()) best = std::min(best, glm::length(j.center_mm - e));
    EXPECT_LT(best, 2.0) << e.x << " " << e.y << " " << e.z;
  }
  // The root segment starts at the inlet (the widest free end).
  EXPECT_NEAR(glm::length(built.model.segments.front().points.front().pos_mm), 0.0, 1e-9);
  EXPECT_EQ(built.model.segments.front().points.front().radius_mm, 3.0);
}

TEST(NetworkBuilder, AlreadySplitNetworksInAnyOrderAndDirection) {
  // One polyline per branch sharing end points, listed leaf first and some reversed; and a
  // confluence (two branches ending where a third starts).
  auto parent = straight({0, 0, 0}, {0, 0, 30}, 2.5);
  auto left = straight({0, 0, 30}, {12, 0, 55}, 1.8);
  auto right = straight({0, 0, 30}, {-12, 0, 55}, 1.8);
  std::reverse(right.begin(), right.end());
  const NetworkBuild tree = build_network(std::vector<Polyline>{line(left), line(right), line(parent)});
  expect_network(tree, 3, 1, 0);
  const auto va = straight({-8, 0, 0}, {0, 0, 30}, 1.6);
  const auto vb = straight({8, 0, 0}, {0, 0, 30}, 1.6);
  const auto basilar = straight({0, 0, 30}, {0, 0, 60}, 1.65);
  expect_network(build_network(std::vector<Polyline>{line(va), line(vb), line(basilar)}), 3, 1, 0);
}

// Segmentation tools leave curve ends short of the vessel they branch from or continue (a public
// 21-curve Slicer arch imported as 5 components): an end within kJoinRadii of the wider radius
// is bridged to its nearest point there; one farther away stays a free end.
TEST(NetworkBuilder, CurveEndsShortOfAnotherVesselAreJoinedThere) {
  const auto arch = straight({0, 0, 0}, {0, 0, 60}, 5.0);
  // A branch starting 3 mm off the arch's side (r 5, so within 2 radii), one continuing the
  // arch after a 2.5 mm gap, and one 12 mm away (> 2 radii of 5 mm: not joined).
  const auto branch = straight({3 + 5, 0, 30}, {30, 0, 45}, 2.0);
  const auto continuation = straight({0, 0, 62.5}, {0, 0, 90}, 5.0);
  const auto stray = straight({0, 22, 30}, {0, 40, 30}, 2.0);
  const NetworkBuild joined = build_network(std::vector<Polyline>{line(arch), line(branch), line(continuation)});
  expect_network(joined, 3, 1, 0);
  EXPECT_EQ(joined.stats.components, 1u);
  EXPECT_EQ(joined.stats.ends_joined, 2u);
  EXPECT_NEAR(joined.stats.widest_join_gap_mm, 3.0 + 5.0, 1e-9);  // the branch: to the arch's axis
  const NetworkBuild apart = build_network(std::vector<Polyline>{line(arch), line(stray)});
  ASSERT_TRUE(apart.ok()) << apart.error;
  EXPECT_EQ(apart.stats.components, 2u);
  EXPECT_EQ(apart.stats.ends_joined, 0u);
}

// A branch stopping short of its parent's wall: the same radius as the parent (1 mm), its end
// 2.9 mm from the parent's axis, 0.9 mm short of where its tube would touch the wall (centre at
// the parent's radius plus its own, 2 mm). That is beyond kJoinRadii (2 mm), but its axis
// extended 1.9 mm (within kReachRadii, 2 of its radii) enters the parent's lumen: joined there.
// Two vessels side by side (1 mm radii, parallel axes 2.6 mm apart, their ends level, as a
// public 21-curve set's two anterior cerebral arteries end 3.1 mm apart) never enter each
// other's lumen along their own axes: kept apart.
TEST(NetworkBuilder, AnEndShortOfItsParentsWallJoinsAndVesselsSideBySideDoNot) {
  const auto parent = straight({0, 0, 0}, {0, 0, 40}, 1.0);
  const auto branch = straight({0, 2.9, 20}, {0, 20, 20}, 1.0);
  const NetworkBuild joined = build_network(std::vector<Polyline>{line(parent), line(branch)});
  expect_network(joined, 3, 1, 0);
  EXPECT_EQ(joined.stats.components, 1u);
  EXPECT_EQ(joined.stats.ends_joined, 1u);
  EXPECT_NEAR(joined.stats.widest_join_gap_mm, 2.9, 0.05);  // to the parent's axis where it enters
  const auto left = straight({0, 0, 0}, {0, 0, 30}, 1.0);
  const auto right = straight({2.6, 0, 0}, {2.6, 0, 30}, 1.0);
  const NetworkBuild apart = build_network(std::vector<Polyline>{line(left), line(right)});
  ASSERT_TRUE(apart.ok()) << apart.error;
  EXPECT_EQ(apart.stats.components, 2u);
  EXPECT_EQ(apart.stats.ends_joined, 0u);
}

TEST(NetworkBuilder, CyclesAndClosedLoops) {
  // A ring of four arcs with a feeder and a branch (circle-of-Willis-like), and a closed curve.
  std::vector<Polyline> ring;
  const double r = 20.0;
  for (int k = 0; k < 4; ++k) {
    std::vector<CenterlinePoint> arc;
    for (int i = 0; i <= 20; ++i) {
      const double a = (k + i / 20.0) * 3.14159265358979 / 2.0;
      arc.push_back({{r * std::cos(a), r * std::sin(a), 0.0}, 1.2});
    }
    ring.push_back(line(arc));
  }
  ring.push_back(line(straight({r + 25, 0, 0}, {r, 0, 0}, 2.0)));   // feeder ending on the ring
  ring.push_back(line(straight({0, r, 0}, {0, r + 20, 0}, 1.0)));   // branch leaving it
  // The ring's two plain nodes are joined through: two arcs between the feeder's and the
  // branch's nodes, the feeder and the branch.
  expect_network(build_network(ring), 4, 2, 1);
  std::vector<CenterlinePoint> closed;
  for (int i = 0; i <= 40; ++i) {
    const double a = i / 40.0 * 2.0 * 3.14159265358979;
    closed.push_back({{15.0 * std::cos(a), 15.0 * std::sin(a), 0.0}, 1.0});
  }
  const NetworkBuild loop = build_network(std::vector<Polyline>{line(closed)});
  expect_network(loop, 2, 2, 1);  // split in two so that no segment is its own parent
  // The same loop hanging off the end of a vessel (found by the fuzzer: joining the halves back
  // through their middle node made it its own parent again).
  const NetworkBuild hanging = build_network(std::vector<Polyline>{line(straight({15, 0, -30}, {15, 0, 0}, 1.0)), line(closed)});
  expect_network(hanging, 3, 2, 1);
}

TEST(NetworkBuilder, DuplicatesDroppedShortBranchesBetweenJunctionsContracted) {
  const auto trunk = straight({0, 0, 0}, {0, 0, 40}, 2.0);
  // Two branch points 1.2 mm apart on a 2 mm vessel: contracted into one trifurcation.
  const auto a = straight({0, 0, 40}, {10, 0, 60}, 1.5);
  const auto link = straight({0, 0, 40}, {0, 0, 41.2}, 2.0, 0.3);
  const auto b = straight({0, 0, 41.2}, {-10, 0, 61.2}, 1.5);
  const auto c = straight({0, 0, 41.2}, {0, 12, 61.2}, 1.5);
  const NetworkBuild built = build_network(
      std::vector<Polyline>{line(trunk), line(a), line(link), line(b), line(c), line(trunk)});
  expect_network(built, 4, 1, 0);
  EXPECT_EQ(built.stats.duplicates, 1u);
  EXPECT_EQ(built.stats.contracted, 1u);
}

// A surface skeleton's stub (VMTK's test aorta surface left a 2-point, 0.024 mm free-ended branch
// at a junction of 4-7 mm vessels; the mesher then needed its spherical-hull fallback there): a
// free-ended branch shorter than the junction's radius ends inside the vessels there and is
// pruned. A side branch longer than that radius stays, and so does a short vessel that is the
// whole network.
TEST(NetworkBuilder, FreeEndedStubsInsideTheirJunctionArePruned) {
  std::vector<Branch> branches;
  branches.push_back({line(straight({0, 0, 0}, {0, 0, 40}, 4.0)), 1, 2});
  branches.push_back({line(straight({0, 0, 40}, {15, 0, 70}, 3.0)), 2, 3});
  branches.push_back({line(straight({0, 0, 40}, {-15, 0, 70}, 3.0)), 2, 4});
  branches.push_back({line({{{0, 0, 40}, 3.9}, {{0.02, 0.013, 40.0}, 3.9}}), 2, 5});  // 0.024 mm
  const NetworkBuild built = build_network(branches);
  expect_network(built, 3, 1, 0);
  EXPECT_EQ(built.stats.stubs, 1u);
  EXPECT_NEAR(built.stats.longest_stub_mm, 0.024, 0.001);
  EXPECT_EQ(built.stats.free_ends, 3u);
  const vessel::VesselSurface surface = vessel::build_vessel_surface(built.model);
  ASSERT_TRUE(surface.ok()) << surface.error;
  EXPECT_TRUE(surface.control.fallback_junctions.empty()) << vessel::fallback_summary(surface.control);
  // A 6 mm side branch off the 4 mm trunk reaches out of it (1.5 radii): kept.
  branches.back() = {line(straight({0, 0, 40}, {0, 6, 40}, 1.0)), 2, 5};
  const NetworkBuild side = build_network(branches);
  expect_network(side, 4, 1, 0);
  EXPECT_EQ(side.stats.stubs, 0u);
  // A lone short vessel (no junction) is not a stub.
  std::vector<Branch> lone;
  lone.push_back({line(straight({0, 0, 0}, {0, 0, 1}, 2.0)), 1, 2});
  expect_network(build_network(lone), 1, 0, 0);
}

TEST(NetworkBuilder, ExplicitTopology) {
  // Branches with given nodes (SWC): a root with two children at node 7.
  std::vector<Branch> branches;
  branches.push_back({line(straight({0, 0, 0}, {0, 0, 20}, 2.0)), 1, 7});
  branches.push_back({line(straight({0, 0, 20}, {8, 0, 35}, 1.4)), 7, 9});
  branches.push_back({line(straight({0, 0, 20}, {-8, 0, 35}, 1.4)), 7, 12});
  expect_network(build_network(branches), 3, 1, 0);
  // Everything collapsing to points leaves nothing.
  std::vector<Branch> none;
  none.push_back({line({{{1, 1, 1}, 1.0}, {{1, 1, 1}, 1.0}}), 1, 2});
  EXPECT_FALSE(build_network(none).ok());
}

}  // namespace
}  // namespace cathbox::vessel_import

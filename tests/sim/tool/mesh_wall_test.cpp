// The mesh wall (collision tree) against the analytic tube it approximates, and a rod pushed
// through a meshed bend staying in the lumen.
#include "tool/mesh_wall.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "tool/lumen_axis.hpp"
#include "tool/rod.hpp"
#include "tube_mesh.hpp"

namespace cathbox::tool {
namespace {

TEST(MeshWall, ProbeAgreesWithTheAnalyticTube) {
  const std::vector<glm::dvec3> axis{{0, 0, -5}, {0, 0, 5}, {0, 0, 15}, {0, 0, 25}};
  collision::TreeBuild build = collision::ObbTree::build(testing::tube_mesh(axis, 1.0, 48, 7));
  ASSERT_TRUE(build) << build.error().message;
  const MeshWall wall(*build);
  WallHint hint;
  WallContact c;
  WallProbe probe;
  probe.center_mm = {0.5, 0.0, 10.0};
  probe.radius_mm = 0.2;
  ASSERT_TRUE(wall.probe(probe, hint, c));
  // Inscribed polygon of 48 sides: the wall is within 1 - cos(pi/48) = 0.2% of the radius.
  EXPECT_NEAR(c.distance_mm, 0.5, 0.003);
  EXPECT_NEAR(c.normal.x, 1.0, 0.01);
  EXPECT_EQ(c.segment, 7);
  probe.center_mm = {1.2, 0.0, 10.0};  // outside the lumen
  ASSERT_TRUE(wall.probe(probe, hint, c));
  EXPECT_LT(c.distance_mm, 0.0);
  probe.center_mm = {0.0, 0.0, 10.0};
  probe.range_mm = 0.5;
  EXPECT_FALSE(wall.probe(probe, hint, c));
}

// The hint slots are kept apart per probe pool (wall_model.hpp: the released coils' thread probes
// from pool 1, the haptic thread from pool 0): a node takes a slot of the pool it is probed from,
// a node probed from the other pool moves to a slot of that one, and the answers are the same.
// A wall of one slot has one pool.
TEST(MeshWall, EachProbePoolTakesSlotsOfItsOwn) {
  const std::vector<glm::dvec3> axis{{0, 0, -5}, {0, 0, 5}, {0, 0, 15}, {0, 0, 25}};
  collision::TreeBuild build = collision::ObbTree::build(testing::tube_mesh(axis, 1.0, 48, 7));
  ASSERT_TRUE(build) << build.error().message;
  const MeshWall wall(*build, 8);  // pool 0: slots 0-5, pool 1: slots 6-7
  WallProbe probe;
  probe.radius_mm = 0.2;
  std::vector<WallHint> hints(10);
  std::vector<double> distances;
  for (std::size_t k = 0; k < hints.size(); ++k) {
    probe.center_mm = {0.05 * static_cast<double>(k), 0.0, static_cast<double>(k)};
    WallContact c;
    ASSERT_TRUE(wall.probe(probe, hints[k], c));
    EXPECT_LT(hints[k].index, 6u) << "node " << k;
    distances.push_back(c.distance_mm);
  }
  {
    const ProbePoolScope pool(1);
    EXPECT_EQ(probe_pool(), 1);
    for (std::size_t k = 0; k < hints.size(); ++k) {
      probe.center_mm = {0.05 * static_cast<double>(k), 0.0, static_cast<double>(k)};
      WallContact c;
      ASSERT_TRUE(wall.probe(probe, hints[k], c));
      EXPECT_GE(hints[k].index, 6u) << "node " << k;
      EXPECT_LT(hints[k].index, 8u) << "node " << k;
      EXPECT_NEAR(c.distance_mm, distances[k], 1e-9) << "node " << k;
    }
  }
  EXPECT_EQ(probe_pool(), 0);
  // A wall of one slot: pool 0's. A probe from pool 1 goes cold, with the same answer, and never
  // takes that slot (pool 0's thread may be using it at the same time).
  const MeshWall one(*build, 1);
  WallHint h;
  WallContact c0, c1;
  probe.center_mm = {0.5, 0.0, 10.0};
  ASSERT_TRUE(one.probe(probe, h, c0));
  EXPECT_EQ(h.index, 0u);
  const ProbePoolScope pool(1);
  WallHint cold;
  ASSERT_TRUE(one.probe(probe, cold, c1));
  EXPECT_EQ(cold.index, WallHint{}.index) << "pool 0's slot taken from pool 1";
  EXPECT_EQ(c1.distance_mm, c0.distance_mm);
  EXPECT_EQ(one.cold_slots(1), 0u);
}

// The 90-degree bend of radius 15 mm the probes and rods below walk and are pushed through, its
// tube meshed at `radius_mm`, and their wire: 200 mm at 20 N.mm2 with a 10 mm tip at 1 N.mm2.
std::vector<glm::dvec3> bend_axis() { return testing::bend_points(15.0, M_PI / 2.0, 5.0, 30.0, M_PI / 60.0); }

collision::TreeBuild meshed_bend(double radius_mm) {
  return collision::ObbTree::build(testing::tube_mesh(bend_axis(), radius_mm, 24));
}

ToolSpec wire_with_a_soft_tip() {
  ToolSpec spec;
  spec.sections = {ToolSection{200.0, 0.36, 20.0, 15.0, 0.0}, ToolSection{10.0, 0.36, 1.0, 0.8, 0.0}};
  return spec;
}

// Fused probes (a node that touched the wall gets one sphere query for its contacts and its
// closest point) answer as the two queries do, node by node along walks on a meshed bend that
// touch the wall, leave it and come back; most probes after the first are fused.
TEST(MeshWall, FusedProbesEqualTheTwoQueryProbes) {
  const std::vector<glm::dvec3> axis = bend_axis();
  collision::TreeBuild build = meshed_bend(1.5);
  ASSERT_TRUE(build) << build.error().message;
  MeshWall fused(*build);
  MeshWall plain(*build);
  plain.set_fused_probes(false);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int touching = 0, free = 0;
  for (int node = 0; node < 60; ++node) {
    const glm::dvec3& a = axis[static_cast<std::size_t>(node) % (axis.size() - 1)];
    glm::dvec3 p = a + glm::dvec3(u(rng), u(rng), u(rng));
    WallHint hf, hp;
    WallProbe probe;
    probe.radius_mm = 0.3 + 0.3 * (u(rng) + 1.0);
    for (int s = 0; s < 80; ++s) {
      p += glm::dvec3(u(rng), u(rng), u(rng)) * (s % 10 == 0 ? 0.3 : 0.03);
      probe.center_mm = p;
      WallContact cf, cp;
      const bool rf = fused.probe(probe, hf, cf);
      const bool rp = plain.probe(probe, hp, cp);
      ASSERT_EQ(rf, rp);
      if (!rf) continue;
      EXPECT_DOUBLE_EQ(cf.distance_mm, cp.distance_mm);
      EXPECT_NEAR(glm::length(cf.point_mm - cp.point_mm), 0.0, 1e-9);
      EXPECT_NEAR(glm::length(cf.normal - cp.normal), 0.0, 1e-9);
      EXPECT_EQ(cf.segment, cp.segment);
      ASSERT_EQ(cf.has_second, cp.has_second);
      if (cf.has_second) {
        EXPECT_NEAR(glm::length(cf.second_point_mm - cp.second_point_mm), 0.0, 1e-9);
        EXPECT_NEAR(glm::length(cf.second_normal - cp.second_normal), 0.0, 1e-9);
      }
      (cf.distance_mm - probe.radius_mm < probe.margin_mm ? touching : free) += 1;
    }
  }
  EXPECT_GT(touching, 1000);
  EXPECT_GT(free, 100);
}

// A tick solved again in parts starts each try from the step's start but keeps the wall hints
// its first try left: a rod whose nodes took slots of a new pool on that try (a released coil's
// first solve on its thread) keeps them, warm, through its tries in parts, where it took them
// again, cold, on every try (a hint only speeds a query up: the same answers).
TEST(MeshWall, ARodSolvedAgainInPartsKeepsTheSlotsItsFirstTryTook) {
  collision::TreeBuild build = meshed_bend(1.0);
  ASSERT_TRUE(build) << build.error().message;
  const MeshWall wall(*build);
  RodSettings settings;
  settings.newton_iterations = 2;  // few enough that a long push into the bend ends unconverged
  settings.substeps_max = 4;
  Rod rod(wire_with_a_soft_tip(), settings);
  rod.set_entry({0, 0, -4}, {0, 0, 1});
  for (int i = 1; i <= 100; ++i) {
    rod.set_boundary(0.1 * i, 0.0);
    rod.step(1e-3, wall);
  }
  const ProbePoolScope pool(1);
  rod.set_boundary(13.0, 0.0);
  rod.step(1e-3, wall);
  ASSERT_GT(rod.last_substeps(), 1) << "the step did not need its parts";
  // Each probed node and edge takes one slot of pool 1, once.
  const std::size_t window = rod.node_total() - rod.first_node();
  EXPECT_LE(wall.cold_slots(1), 2 * window) << "slots taken again by the tries in parts";
  EXPECT_GT(wall.cold_slots(1), 0u);
}

TEST(MeshWall, RodThroughAMeshedBendStaysInTheLumen) {
  collision::TreeBuild build = meshed_bend(1.0);
  ASSERT_TRUE(build) << build.error().message;
  const MeshWall wall(*build);
  Rod rod(wire_with_a_soft_tip());
  rod.set_entry({0, 0, -4}, {0, 0, 1});
  double worst = 0.0;
  for (int i = 1; i <= 500; ++i) {
    rod.set_boundary(0.1 * i, 0.01 * i);
    rod.step(1e-3, wall);
    for (std::size_t k = rod.first_free_node(); k < rod.node_total(); ++k) {
      const auto sd = wall.tree().signed_distance(rod.positions()[k]);
      ASSERT_TRUE(sd.has_value());
      worst = std::max(worst, (*sd + rod.node_radius_mm(k)) / rod.node_radius_mm(k));
    }
  }
  EXPECT_LT(worst, 0.10) << "a node left the lumen by more than 10% of its radius";
  // Through the bend: the tip is in the lead-out.
  EXPECT_GT(rod.tip().position_mm.x, 15.0);
  EXPECT_GT(rod.contacts().size(), 0u);
}

}  // namespace
}  // namespace cathbox::tool

#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {
namespace {

// Steering on the bundled Y (vessel module surface, collision tree): the angled tip turned
// towards +x enters the left branch (segment 2), turned half a turn the right one (3).
TEST(MeshWall, SteeringOnTheBundledYBifurcation) {
  const CaseParse c = load_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case");
  ASSERT_TRUE(c) << c.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world.ok()) << world.error().message;
  ASSERT_TRUE((*world)->target().has_value());
  ASSERT_NE((*world)->mesh(), nullptr);
  EXPECT_GT((*world)->mesh()->triangle_count(), 1000u);
  for (const auto& [rotation, branch] : {std::pair{0.0, 2}, std::pair{M_PI, 3}}) {
    Simulator sim((*world)->wall(), c->tools, (*world)->entry());
    for (int i = 1; i <= 1300; ++i) {
      sim.set_insertion(0, 0.03 * i);
      sim.set_rotation(0, rotation * std::min(1.0, i / 1000.0));
      sim.step();
    }
    for (int i = 1; i <= 2750; ++i) {
      sim.set_insertion(0, 39.0 + 0.02 * i);
      sim.step();
    }
    EXPECT_EQ(sim.tip_segment(0), branch) << "rotation " << rotation;
    EXPECT_GT(sim.tip(0).position_mm.z, 75.0);
  }
}

vessel::Segment polyline(std::int32_t id, const std::vector<glm::dvec3>& pts, double radius, std::vector<std::int32_t> parents,
                         std::vector<std::int32_t> children) {
  vessel::Segment s;
  s.id = id;
  s.parents = std::move(parents);
  s.children = std::move(children);
  for (const glm::dvec3& p : pts) s.points.push_back({p, radius});
  return s;
}

// A parent along +z (radius 1.8) ending at the origin's junction with a child going on along
// +x (radius 1.4, a 90-degree corner) and one along -x: the ICA terminus and its branches.
vessel::VesselModel t_junction() {
  std::vector<glm::dvec3> parent, right, left;
  for (int i = -20; i <= 0; ++i) parent.push_back({0, 0, i});
  for (int i = 0; i <= 20; ++i) right.push_back({i, 0, 0});
  for (int i = 0; i <= 20; ++i) left.push_back({-i, 0, 0});
  vessel::VesselModel m;
  m.segments = {polyline(1, parent, 1.8, {}, {2, 3}), polyline(2, right, 1.4, {1}, {}), polyline(3, left, 1.2, {1}, {})};
  return m;
}

// Away from a junction the lumen is the centreline's tube exactly: the clearance R - d, the
// normal radial, the wall point on the tube; the range as the mesh's.
TEST(LumenAxis, AlongASegmentItIsTheTubeRoundTheCentreline) {
  const vessel::VesselModel m = t_junction();
  const LumenAxis axis(m);
  AxisHint hint;
  WallContact c;
  WallProbe probe;
  probe.center_mm = {0.6, 0.8, -10.3};
  probe.radius_mm = 0.5;
  ASSERT_EQ(axis.probe(probe, hint, c), LumenAxis::Answer::kWall);
  EXPECT_NEAR(c.distance_mm, 1.8 - 1.0, 1e-12);
  EXPECT_NEAR(glm::distance(c.normal, glm::dvec3(0.6, 0.8, 0.0)), 0.0, 1e-12);
  EXPECT_NEAR(glm::distance(c.point_mm, glm::dvec3(1.08, 1.44, -10.3)), 0.0, 1e-12);
  EXPECT_EQ(c.segment, 1);
  probe.center_mm = {0.0, 2.5, -10.0};  // outside
  ASSERT_EQ(axis.probe(probe, hint, c), LumenAxis::Answer::kWall);
  EXPECT_NEAR(c.distance_mm, -0.7, 1e-12);
  probe.center_mm = {0.0, 0.0, -10.0};
  probe.range_mm = 1.0;  // the node's surface 1.3 mm from the wall
  EXPECT_EQ(axis.probe(probe, hint, c), LumenAxis::Answer::kClear);
  const vessel::VesselModel empty;
  EXPECT_EQ(LumenAxis(empty).probe(probe, hint, c), LumenAxis::Answer::kNone);
}

// A node dragged from the parent round the junction's inner corner into the right branch: the
// coherent probe (hint climbing along, looking into the neighbours) answers as a fresh scan
// with the neighbours, and the answer is continuous: the normal turns by a few degrees per
// 0.05 mm step where the union of the tubes has a 90-degree crease, and the clearance is never
// less than the union's (the lumen is not narrowed) nor more than kBlend ln 3 above it.
TEST(LumenAxis, CoherentAndSmoothRoundAJunctionsInnerCorner) {
  const vessel::VesselModel m = t_junction();
  const LumenAxis axis(m);
  AxisHint coherent;
  WallContact last;
  double worst_turn = 0.0;
  for (int i = 0; i <= 160; ++i) {
    // An L-shaped path off both axes: up the parent, then along the branch.
    const double s = -4.0 + 0.05 * i;
    WallProbe probe;
    probe.center_mm = s < 0.0 ? glm::dvec3(0.6, 0.3, s - 0.4) : glm::dvec3(0.6 + s, 0.3, -0.4);
    probe.radius_mm = 1.0;
    WallContact c, fresh_c;
    AxisHint fresh;
    ASSERT_EQ(axis.probe(probe, coherent, c), LumenAxis::Answer::kWall);
    (void)axis.probe(probe, fresh, fresh_c);
    EXPECT_NEAR(c.distance_mm, fresh_c.distance_mm, 1e-9) << i;
    const glm::dvec3 p = probe.center_mm;
    const double in_parent = 1.8 - glm::length(glm::dvec3(p.x, p.y, std::max(0.0, p.z)));
    const double in_right = 1.4 - glm::length(glm::dvec3(std::min(0.0, p.x), p.y, p.z));
    const double in_left = 1.2 - glm::length(glm::dvec3(std::max(0.0, p.x), p.y, p.z));
    const double union_mm = std::max({in_parent, in_right, in_left});
    EXPECT_GE(c.distance_mm, union_mm - 1e-9) << i;
    EXPECT_LE(c.distance_mm, union_mm + LumenAxis::kBlend_mm * std::log(3.0) + 1e-9) << i;
    if (i > 0) worst_turn = std::max(worst_turn, std::acos(std::clamp(glm::dot(c.normal, last.normal), -1.0, 1.0)));
    last = c;
  }
  std::printf("round the junction: the normal turns at most %.1f degrees per 0.05 mm\n", worst_turn * 180.0 / M_PI);
  EXPECT_LT(worst_turn * 180.0 / M_PI, 10.0);
}

// Through a meshed wall: a probe with lumen_axis is answered by the tube round the surface
// model's centreline (the normal radial wherever the node is), one without by the facets (an
// 8-sided tube's normals take 8 directions).
TEST(MeshWall, AnExpandedNodeIsHeldByTheCentrelineTubeNotTheFacets) {
  const std::vector<glm::dvec3> pts{{0, 0, -5}, {0, 0, 5}, {0, 0, 15}, {0, 0, 25}};
  auto surface = std::make_shared<WallSurface>();
  surface->mesh = testing::tube_mesh(pts, 1.4, 8, 4);
  surface->model.segments.push_back(polyline(4, pts, 1.4, {}, {}));
  collision::TreeBuild build = collision::ObbTree::build(surface->mesh);
  ASSERT_TRUE(build) << build.error().message;
  const MeshWall wall(*build, MeshWall::kDefaultHintSlots, surface);
  double facet_miss = 0.0, tube_miss = 0.0;
  for (int i = 0; i < 36; ++i) {
    const double a = 2.0 * M_PI * i / 36.0 + 0.01;
    const glm::dvec3 radial(std::cos(a), std::sin(a), 0.0);
    WallProbe probe;
    probe.center_mm = glm::dvec3(0, 0, 10) + 0.15 * radial;
    probe.radius_mm = 1.2;
    probe.second_wall = false;
    WallHint hint;
    WallContact facet, tube;
    ASSERT_TRUE(wall.probe(probe, hint, facet));
    probe.lumen_axis = true;
    ASSERT_TRUE(wall.probe(probe, hint, tube));
    EXPECT_NEAR(tube.distance_mm, 1.4 - 0.15, 1e-12);
    EXPECT_EQ(tube.segment, 4);
    tube_miss = std::max(tube_miss, glm::distance(tube.normal, radial));
    facet_miss = std::max(facet_miss, glm::distance(facet.normal, radial));
  }
  EXPECT_LT(tube_miss, 1e-12);
  EXPECT_GT(facet_miss, 0.3);  // up to 22.5 degrees off
}

}  // namespace
}  // namespace cathbox::tool

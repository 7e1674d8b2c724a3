// The mesh wall (collision tree) against the analytic tube it approximates, and a rod pushed
// through a meshed bend staying in the lumen.
#include "tool/mesh_wall.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "analytic_walls.hpp"
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

// Fused probes (a node that touched the wall gets one sphere query for its contacts and its
// closest point) answer as the two queries do, node by node along walks on a meshed bend that
// touch the wall, leave it and come back; most probes after the first are fused.
TEST(MeshWall, FusedProbesEqualTheTwoQueryProbes) {
  const std::vector<glm::dvec3> axis = testing::bend_points(15.0, M_PI / 2.0, 5.0, 30.0, M_PI / 60.0);
  collision::TreeBuild build = collision::ObbTree::build(testing::tube_mesh(axis, 1.5, 24));
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

TEST(MeshWall, RodThroughAMeshedBendStaysInTheLumen) {
  const std::vector<glm::dvec3> axis = testing::bend_points(15.0, M_PI / 2.0, 5.0, 30.0, M_PI / 60.0);
  collision::TreeBuild build = collision::ObbTree::build(testing::tube_mesh(axis, 1.0, 24));
  ASSERT_TRUE(build) << build.error().message;
  const MeshWall wall(*build);
  ToolSpec spec;
  spec.sections = {ToolSection{200.0, 0.36, 20.0, 15.0, 0.0}, ToolSection{10.0, 0.36, 1.0, 0.8, 0.0}};
  Rod rod(spec);
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

}  // namespace
}  // namespace cathbox::tool

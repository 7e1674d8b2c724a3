#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "collision/obb_tree.hpp"
#include "mesh_factory.hpp"

namespace cathbox::collision {
namespace {

vessel::SurfaceMesh one_triangle() {
  vessel::SurfaceMesh m;
  m.positions_mm = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.triangles = {0, 1, 2};
  m.triangle_regions = {{}};
  return m;
}

void expect_rejected(const vessel::SurfaceMesh& m, const std::string& field) {
  const TreeBuild b = ObbTree::build(m);
  EXPECT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find(field), std::string::npos) << b.error().message;
  EXPECT_EQ(b.error().message.find('\n'), std::string::npos);
}

TEST(ObbTreeBuild, RejectsEmptyMesh) { expect_rejected(vessel::SurfaceMesh{}, "surface_mesh.triangles"); }

TEST(ObbTreeBuild, RejectsIndexOutOfRange) {
  auto m = one_triangle();
  m.triangles[2] = 7;
  expect_rejected(m, "surface_mesh.triangles[2]");
}

TEST(ObbTreeBuild, RejectsNonFinitePosition) {
  auto m = one_triangle();
  m.positions_mm[1].y = std::numeric_limits<float>::quiet_NaN();
  expect_rejected(m, "surface_mesh.positions_mm[1]");
  m.positions_mm[1].y = std::numeric_limits<float>::infinity();
  expect_rejected(m, "surface_mesh.positions_mm[1]");
}

TEST(ObbTreeBuild, RejectsRegionCountMismatch) {
  auto m = one_triangle();
  m.triangle_regions.clear();
  expect_rejected(m, "surface_mesh.triangle_regions");
}

TEST(ObbTreeBuild, RejectsPartialTriangle) {
  auto m = one_triangle();
  m.triangles.push_back(0);
  expect_rejected(m, "multiple of 3");
}

TEST(ObbTreeBuild, RejectsAllDegenerate) {
  auto m = one_triangle();
  m.positions_mm[2] = {2, 0, 0};
  expect_rejected(m, "degenerate");
}

TEST(ObbTreeBuild, RejectsBadMargin) {
  BuildOptions o;
  o.coherence_margin_mm = std::nan("");
  const TreeBuild b = ObbTree::build(one_triangle(), o);
  EXPECT_FALSE(b);
  EXPECT_NE(b.error().message.find("coherence_margin_mm"), std::string::npos);
}

TEST(ObbTreeBuild, SingleTriangle) {
  const TreeBuild b = ObbTree::build(one_triangle());
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_EQ(b->stats().triangles, 1u);
  EXPECT_FALSE(b->stats().closed);
  const auto c = b->closest_point({0.25, 0.25, 2.0});
  ASSERT_TRUE(c);
  EXPECT_DOUBLE_EQ(c->distance_mm, 2.0);
  EXPECT_EQ(c->feature, FeatureKind::kFace);
}

TEST(ObbTreeBuild, ClosedTubeStats) {
  const auto m = testing::make_knot_tube(200, 12);
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  const TreeStats& s = b->stats();
  EXPECT_TRUE(s.closed);
  EXPECT_TRUE(s.consistently_oriented);
  EXPECT_EQ(s.triangles, m.triangle_count());
  EXPECT_EQ(s.degenerate_dropped, 0u);
  EXPECT_GE(s.regions, 40u);  // 40 segments/junctions + 2 caps
  EXPECT_GE(4 * s.leaves, s.triangles);
  EXPECT_GT(s.depth, 2u);
}

TEST(ObbTreeBuild, DropsDegenerateTriangles) {
  const auto m = testing::make_soup(300, 3);
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  // Every 29th (coincident corners) and 31st (collinear) triangle has no area.
  EXPECT_GE(b->stats().degenerate_dropped, 300u / 31u);
  EXPECT_EQ(b->stats().triangles + b->stats().degenerate_dropped, 300u);
}

}  // namespace
}  // namespace cathbox::collision

#include "app/tube_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include <glm/geometric.hpp>

namespace cathbox::app {
namespace {

std::vector<glm::vec3> arc(int n, float radius_mm) {
  std::vector<glm::vec3> p;
  for (int i = 0; i < n; ++i) {
    const float a = 1.5F * static_cast<float>(i) / static_cast<float>(n - 1);
    p.emplace_back(radius_mm * std::cos(a), radius_mm * std::sin(a), 0.3F * static_cast<float>(i));
  }
  return p;
}

TEST(TubeMesh, EveryVertexIsOneRadiusFromItsNodeWithARadialNormal) {
  const std::vector<glm::vec3> nodes = arc(40, 20.0F);
  TubeMesh t;
  t.build(nodes, {}, 0.4F, 8);
  ASSERT_EQ(t.positions_mm.size(), TubeMesh::vertex_count(nodes.size(), 8));
  ASSERT_EQ(t.triangles.size(), TubeMesh::index_count(nodes.size(), 8));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (std::size_t k = 0; k < 8; ++k) {
      const glm::vec3 v = t.positions_mm[i * 8 + k];
      EXPECT_NEAR(glm::distance(v, nodes[i]), 0.4F, 1e-4F);
      EXPECT_NEAR(glm::dot(glm::normalize(v - nodes[i]), t.normals[i * 8 + k]), 1.0F, 1e-4F);
    }
  }
}

TEST(TubeMesh, TrianglesFaceOutwardAndTheSurfaceHasOnlyTheProximalOpening) {
  const std::vector<glm::vec3> nodes = arc(12, 10.0F);
  TubeMesh t;
  t.build(nodes, {}, 0.5F, 6);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t f = 0; f < t.triangles.size(); f += 3) {
    const glm::vec3 a = t.positions_mm[t.triangles[f]];
    const glm::vec3 b = t.positions_mm[t.triangles[f + 1]];
    const glm::vec3 c = t.positions_mm[t.triangles[f + 2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    const glm::vec3 avg_normal = t.normals[t.triangles[f]] + t.normals[t.triangles[f + 1]] +
                                 t.normals[t.triangles[f + 2]];
    EXPECT_GT(glm::dot(n, avg_normal), 0.0F) << "triangle " << f / 3;
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t u = t.triangles[f + static_cast<std::size_t>(e)];
      const std::uint32_t v = t.triangles[f + static_cast<std::size_t>((e + 1) % 3)];
      ++edges[{std::min(u, v), std::max(u, v)}];
    }
  }
  int boundary = 0;
  for (const auto& [edge, count] : edges) {
    EXPECT_LE(count, 2);
    if (count == 1) ++boundary;
  }
  EXPECT_EQ(boundary, 6);  // the open proximal ring only
}

TEST(TubeMesh, FollowsTheGivenFramesAndRebuildsWithoutGrowing) {
  const std::vector<glm::vec3> nodes = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<glm::vec3> frames(3, glm::vec3(0, 0, 1));
  TubeMesh t;
  t.build(nodes, frames, 1.0F, 4);
  EXPECT_NEAR(glm::distance(t.positions_mm[0], glm::vec3(0, 0, 1)), 0.0F, 1e-5F);
  const auto* data = t.positions_mm.data();
  t.build(nodes, frames, 1.0F, 4);
  EXPECT_EQ(t.positions_mm.data(), data);
}

TEST(TubeMesh, DegenerateInputGivesAnEmptyMesh) {
  TubeMesh t;
  const std::vector<glm::vec3> one = {{1, 2, 3}};
  t.build(one, {}, 1.0F);
  EXPECT_TRUE(t.triangles.empty());
  // Repeated nodes and a NaN-free result for coincident points.
  const std::vector<glm::vec3> same = {{1, 1, 1}, {1, 1, 1}, {2, 1, 1}};
  t.build(same, {}, 1.0F);
  for (const glm::vec3& p : t.positions_mm) EXPECT_FALSE(std::isnan(p.x + p.y + p.z));
}

}  // namespace
}  // namespace cathbox::app

#include "app/mesh_chunks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "tube_fixture.hpp"

namespace cathbox::app {
namespace {

using Tri = std::array<std::uint32_t, 3>;

std::multiset<Tri> triangle_set(const std::vector<std::uint32_t>& t) {
  std::multiset<Tri> s;
  for (std::size_t i = 0; i + 2 < t.size(); i += 3) s.insert({t[i], t[i + 1], t[i + 2]});
  return s;
}

TEST(MeshChunks, EveryTriangleOnceInAChunkWhoseBoxHoldsIt) {
  const testing::FixtureMesh tube = testing::straight_tube(-50.0F, 50.0F, 4.0F, 51, 12);
  const ChunkedMesh c = ChunkedMesh::build(tube.positions_mm, tube.triangles, 10.0F);
  EXPECT_EQ(triangle_set(c.triangles), triangle_set(tube.triangles));
  EXPECT_GE(c.chunks.size(), 10U);
  std::uint32_t next = 0;
  for (const MeshChunk& ch : c.chunks) {
    EXPECT_EQ(ch.first_index, next);  // contiguous, in order
    next += ch.index_count;
    for (std::uint32_t i = ch.first_index; i < ch.first_index + ch.index_count; ++i) {
      const glm::vec3 p = tube.positions_mm[c.triangles[i]];
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, ch.min_mm)) && glm::all(glm::lessThanEqual(p, ch.max_mm)));
    }
  }
  EXPECT_EQ(next, c.triangles.size());
}

TEST(MeshChunks, OutOfRangeIndicesAreDropped) {
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<std::uint32_t> t = {0, 1, 2, 0, 1, 7};
  const ChunkedMesh c = ChunkedMesh::build(p, t, 5.0F);
  EXPECT_EQ(c.triangles.size(), 3U);
  EXPECT_TRUE(ChunkedMesh::build({}, t, 5.0F).chunks.empty());
}

TEST(MeshChunks, CullsBehindTheCameraAndBeyondTheDistanceAndMergesNeighbours) {
  const testing::FixtureMesh tube = testing::straight_tube(-50.0F, 50.0F, 4.0F, 101, 12);
  const ChunkedMesh c = ChunkedMesh::build(tube.positions_mm, tube.triangles, 10.0F);
  // Inside the tube at x = 0 looking down +X.
  const glm::vec3 eye{0.0F, 0.0F, 0.0F};
  const glm::mat4 vp = glm::perspective(1.2F, 1.0F, 0.05F, 200.0F) *
                       glm::lookAt(eye, glm::vec3(1, 0, 0), glm::vec3(0, 0, 1));
  std::vector<IndexRange> all;
  visible_ranges(c.chunks, vp, eye, 0.0F, all);
  std::vector<IndexRange> near;
  visible_ranges(c.chunks, vp, eye, 20.0F, near);
  auto covered = [&](const std::vector<IndexRange>& rs, float& min_x, float& max_x) {
    std::size_t n = 0;
    min_x = 1e9F;
    max_x = -1e9F;
    for (const IndexRange& r : rs) {
      n += r.index_count;
      for (std::uint32_t i = r.first_index; i < r.first_index + r.index_count; ++i) {
        min_x = std::min(min_x, tube.positions_mm[c.triangles[i]].x);
        max_x = std::max(max_x, tube.positions_mm[c.triangles[i]].x);
      }
    }
    return n;
  };
  float lo = 0.0F;
  float hi = 0.0F;
  const std::size_t n_all = covered(all, lo, hi);
  EXPECT_GT(lo, -15.0F);  // what lies well behind the eye is culled
  EXPECT_NEAR(hi, 50.0F, 1e-4F);
  EXPECT_LT(n_all, c.triangles.size() * 3 / 4);
  const std::size_t n_near = covered(near, lo, hi);
  EXPECT_LT(hi, 35.0F);  // and beyond 20 mm (plus one cell) too
  EXPECT_LT(n_near, n_all);
  // Neighbouring chunks merge: far fewer ranges than chunks.
  EXPECT_LE(all.size(), 3U);
}

TEST(MeshChunks, BoxInFrustum) {
  const glm::mat4 vp = glm::perspective(1.0F, 1.0F, 1.0F, 100.0F) *
                       glm::lookAt(glm::vec3(0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
  EXPECT_TRUE(box_in_frustum(vp, glm::vec3(-1, -1, -11), glm::vec3(1, 1, -9)));
  EXPECT_FALSE(box_in_frustum(vp, glm::vec3(-1, -1, 9), glm::vec3(1, 1, 11)));     // behind
  EXPECT_FALSE(box_in_frustum(vp, glm::vec3(50, -1, -11), glm::vec3(60, 1, -9)));  // far right
  EXPECT_FALSE(box_in_frustum(vp, glm::vec3(-1, -1, -300), glm::vec3(1, 1, -200)));  // too far
  EXPECT_TRUE(box_in_frustum(vp, glm::vec3(-100, -100, -50), glm::vec3(100, 100, 50)));  // around
}

}  // namespace
}  // namespace cathbox::app

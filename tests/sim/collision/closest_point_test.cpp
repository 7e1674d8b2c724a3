#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "test_meshes.hpp"

namespace cathbox::collision {
namespace {

using testing::near_rel;

class ClosestPointTest : public ::testing::TestWithParam<int> {
 protected:
  static void SetUpTestSuite() {
    meshes_ = new std::vector<testing::NamedMesh>(testing::exactness_meshes());
  }
  static void TearDownTestSuite() {
    delete meshes_;
    meshes_ = nullptr;
  }
  const testing::NamedMesh& named() const { return (*meshes_)[static_cast<std::size_t>(GetParam())]; }
  static std::vector<testing::NamedMesh>* meshes_;
};
std::vector<testing::NamedMesh>* ClosestPointTest::meshes_ = nullptr;

TEST_P(ClosestPointTest, EqualsBruteForceNearAndFar) {
  const auto& m = named().mesh;
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  for (const glm::dvec3& p : testing::query_points(m, 400, 2.0, 21)) {
    const testing::BruteNearest want = testing::nearest(m, p);
    const auto got = b->closest_point(p);
    ASSERT_TRUE(got);
    ASSERT_TRUE(near_rel(got->distance_mm, want.distance)) << named().name << " " << got->distance_mm << " vs " << want.distance;
    // The point lies on the reported face, at the reported distance.
    const auto f = static_cast<std::size_t>(got->face);
    EXPECT_LT(testing::point_triangle_distance(got->point_mm, testing::corner(m, f, 0), testing::corner(m, f, 1),
                                               testing::corner(m, f, 2)),
              1e-9);
    EXPECT_TRUE(near_rel(glm::length(p - got->point_mm), want.distance));
    EXPECT_EQ(got->region, m.triangle_regions[f]);
    EXPECT_NEAR(glm::length(got->normal), 1.0, 1e-9);
    EXPECT_DOUBLE_EQ(std::abs(got->signed_distance_mm), got->distance_mm);
  }
}

TEST_P(ClosestPointTest, MaxDistanceIsInclusiveAndExact) {
  const auto& m = named().mesh;
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> frac(0.5, 1.5);
  for (const glm::dvec3& p : testing::query_points(m, 200, 1.0, 22)) {
    const double want = testing::nearest(m, p).distance;
    const double limit = want * frac(rng);
    const auto got = b->closest_point(p, limit);
    if (want <= limit * (1.0 - 1e-9)) {
      ASSERT_TRUE(got);
      EXPECT_TRUE(near_rel(got->distance_mm, want));
    } else if (want > limit * (1.0 + 1e-9)) {
      EXPECT_FALSE(got);
    }
  }
}

// The sign of the distance is defined for closed meshes only: these run on the closed ones.
class ClosedMeshSignTest : public ClosestPointTest {};

TEST_P(ClosedMeshSignTest, SignMatchesRayParity) {
  ASSERT_TRUE(named().closed) << named().name;
  const auto& m = named().mesh;
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  int inside = 0;
  for (const glm::dvec3& p : testing::query_points(m, 300, 1.0, 23)) {
    const auto s = b->signed_distance(p);
    ASSERT_TRUE(s);
    if (std::abs(*s) < 1e-6) continue;  // parity is ill-posed on the wall
    const bool want = testing::inside_by_parity(m, p);
    EXPECT_EQ(*s < 0.0, want) << named().name << " sd " << *s;
    EXPECT_EQ(*b->contains(p), want);
    inside += want;
  }
  EXPECT_GT(inside, 30);
}

// Just off vertices and edges (where only the pseudo-normal of the closest vertex or edge gives
// a reliable sign), the inside test agrees with ray parity.
TEST_P(ClosedMeshSignTest, SignIsRobustNextToVerticesAndEdges) {
  ASSERT_TRUE(named().closed) << named().name;
  const auto& m = named().mesh;
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  int checked = 0;
  auto check = [&](const glm::dvec3& p) {
    const double sd = *b->signed_distance(p);
    if (std::abs(sd) < 1e-9) return;
    EXPECT_EQ(sd < 0.0, testing::inside_by_parity(m, p)) << named().name << " sd " << sd;
    ++checked;
  };
  for (std::size_t v = 0; v < m.positions_mm.size(); v += 11) {
    const glm::dvec3 p(m.positions_mm[v]);
    const glm::dvec3 n(m.normals[v]);
    for (double eps : {1e-3, 1e-5}) {
      check(p - eps * n);
      check(p + eps * n);
    }
    const auto on = b->closest_point(p);
    ASSERT_TRUE(on);
    EXPECT_LT(on->distance_mm, 1e-12);
    EXPECT_EQ(on->feature, FeatureKind::kVertex);
  }
  for (std::size_t t = 0; t < m.triangle_count(); t += 13) {
    const glm::dvec3 mid = 0.5 * (testing::corner(m, t, 0) + testing::corner(m, t, 1));
    const glm::dvec3 n = glm::normalize(glm::cross(testing::corner(m, t, 1) - testing::corner(m, t, 0),
                                                   testing::corner(m, t, 2) - testing::corner(m, t, 0)));
    check(mid - 1e-5 * n);
    check(mid + 1e-5 * n);
  }
  EXPECT_GT(checked, 200);
}

std::string mesh_name(const ::testing::TestParamInfo<int>& info) {
  static const char* const kNames[] = {"soup", "bumpy_sphere", "knot_tube", "tapered_tube"};
  return kNames[info.param];
}

INSTANTIATE_TEST_SUITE_P(Meshes, ClosestPointTest, ::testing::Values(0, 1, 2, 3), mesh_name);
INSTANTIATE_TEST_SUITE_P(ClosedMeshes, ClosedMeshSignTest, ::testing::Values(1, 2, 3), mesh_name);

TEST(ClosestPointBadInput, NanAndNegativeGiveEmpty) {
  const TreeBuild b = ObbTree::build(testing::make_bumpy_sphere(10, 12, 3.0, 0.0, 1));
  ASSERT_TRUE(b);
  const double nan = testing::kNaN;
  const double inf = testing::kInf;
  EXPECT_FALSE(b->closest_point({nan, 0, 0}));
  EXPECT_FALSE(b->closest_point({0, inf, 0}));
  EXPECT_FALSE(b->closest_point({0, 0, 0}, nan));
  EXPECT_FALSE(b->closest_point({0, 0, 0}, -1.0));
  EXPECT_FALSE(b->signed_distance({0, 0, nan}));
  EXPECT_FALSE(b->contains({nan, nan, nan}));
  QueryHint hint;
  EXPECT_FALSE(b->closest_point({nan, 0, 0}, inf, hint));
  // Far away still works (no overflow in the float bounds).
  const auto far = b->closest_point({1e12, -3e11, 5e10});
  ASSERT_TRUE(far);
  EXPECT_GT(far->signed_distance_mm, 0.0);
  EXPECT_TRUE(*b->contains({0, 0, 0}));
}

}  // namespace
}  // namespace cathbox::collision

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "test_meshes.hpp"

namespace cathbox::collision {
namespace {

using testing::near_rel;

TEST(RayCast, FirstHitEqualsBruteForce) {
  for (const auto& named : testing::exactness_meshes()) {
    const auto& m = named.mesh;
    const TreeBuild b = ObbTree::build(m);
    ASSERT_TRUE(b) << b.error().message;
    std::mt19937 rng(51);
    std::uniform_real_distribution<double> scale(0.1, 10.0);
    int hits = 0;
    for (const glm::dvec3& o : testing::query_points(m, 300, 3.0, 52)) {
      const glm::dvec3 dir = scale(rng) * testing::random_unit(rng);  // not unit on purpose
      const auto want = testing::first_hit(m, o, dir);
      const auto got = b->ray_cast(o, dir);
      ASSERT_EQ(got.has_value(), want.has_value()) << named.name;
      if (!got) continue;
      ++hits;
      EXPECT_TRUE(near_rel(got->t, *want, 1e-6, 1e-12)) << named.name << " " << got->t << " vs " << *want;
      EXPECT_NEAR(glm::length(got->point_mm - (o + got->t * dir)), 0.0, 1e-9);
      EXPECT_EQ(got->region, m.triangle_regions[static_cast<std::size_t>(got->face)]);
      EXPECT_EQ(got->front_face, glm::dot(dir, got->normal) < 0.0);
      // Limited to just before the hit: nothing.
      EXPECT_FALSE(b->ray_cast(o, dir, got->t * (1.0 - 1e-6)));
    }
    EXPECT_GT(hits, 100) << named.name;
  }
}

TEST(RayCast, FromInsideHitsTheWallFromBehind) {
  const auto m = testing::make_bumpy_sphere(20, 30, 4.0, 0.0, 1);
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b);
  const auto hit = b->ray_cast({0.1, 0.2, 0.3}, {0.0, 0.0, 1.0});
  ASSERT_TRUE(hit);
  EXPECT_FALSE(hit->front_face);
  EXPECT_NEAR(hit->point_mm.z, 4.0, 0.05);
}

TEST(RayCast, BadInputGivesNothing) {
  const TreeBuild b = ObbTree::build(testing::make_bumpy_sphere(10, 12, 3.0, 0.0, 1));
  ASSERT_TRUE(b);
  const double nan = testing::kNaN;
  EXPECT_FALSE(b->ray_cast({0, 0, 0}, {0, 0, 0}));
  EXPECT_FALSE(b->ray_cast({nan, 0, 0}, {1, 0, 0}));
  EXPECT_FALSE(b->ray_cast({0, 0, 0}, {1, nan, 0}));
  EXPECT_FALSE(b->ray_cast({0, 0, 0}, {1, 0, 0}, -1.0));
  EXPECT_FALSE(b->ray_cast({0, 0, 0}, {1, 0, 0}, nan));
  EXPECT_TRUE(b->ray_cast({0, 0, 0}, {1, 0, 0}));
  // Axis-parallel rays along box faces still work.
  EXPECT_TRUE(b->ray_cast({-10, 0, 0}, {1, 0, 0}));
}

}  // namespace
}  // namespace cathbox::collision

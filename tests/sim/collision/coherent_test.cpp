#include <array>
#include <cmath>

#include <gtest/gtest.h>

#include "test_meshes.hpp"

namespace cathbox::collision {
namespace {

// The same answer, whichever of several equally near triangles reported it.
void expect_same(const ClosestPoint& a, const ClosestPoint& b) {
  EXPECT_DOUBLE_EQ(a.distance_mm, b.distance_mm);
  EXPECT_DOUBLE_EQ(a.signed_distance_mm, b.signed_distance_mm);
  EXPECT_NEAR(glm::length(a.point_mm - b.point_mm), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(a.normal - b.normal), 0.0, 1e-9);
  if (a.face == b.face) {
    EXPECT_EQ(a.region, b.region);
  }
}

// Tool nodes wandering inside a vessel in steps of up to 0.1 mm: the coherent queries give
// exactly the cold answers, and most of them come from the hint.
TEST(Coherent, RandomWalksEqualColdQueries) {
  const auto m = testing::make_knot_tube(400, 16);
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  std::mt19937 rng(61);
  std::uniform_real_distribution<double> step(0.0, 0.1);
  std::uint32_t hits = 0;
  std::uint32_t refills = 0;
  for (int node = 0; node < 40; ++node) {
    glm::dvec3 p = testing::random_surface_point(m, rng) + 0.8 * testing::random_unit(rng);
    QueryHint closest_hint;
    QueryHint sphere_hint;
    QueryHint capsule_hint;
    for (int s = 0; s < 60; ++s) {
      p += step(rng) * testing::random_unit(rng);
      const auto cold = b->closest_point(p, 3.0);
      const auto warm = b->closest_point(p, 3.0, closest_hint);
      ASSERT_EQ(cold.has_value(), warm.has_value());
      if (cold) expect_same(*cold, *warm);
      std::array<Contact, 8> a{}, c{};
      const std::size_t na = b->sphere_contacts(p, 0.6, a);
      const std::size_t nc = b->sphere_contacts(p, 0.6, c, sphere_hint);
      ASSERT_EQ(na, nc);
      for (std::size_t i = 0; i < na; ++i) EXPECT_NEAR(a[i].depth_mm, c[i].depth_mm, 1e-12);
      const glm::dvec3 q = p + glm::dvec3{0.3, 0.0, 0.0};
      const std::size_t ka = b->capsule_contacts(p, q, 0.4, a);
      const std::size_t kc = b->capsule_contacts(p, q, 0.4, c, capsule_hint);
      ASSERT_EQ(ka, kc);
      for (std::size_t i = 0; i < ka; ++i) EXPECT_NEAR(a[i].depth_mm, c[i].depth_mm, 1e-12);
    }
    hits += closest_hint.hits() + sphere_hint.hits() + capsule_hint.hits();
    refills += closest_hint.refills() + sphere_hint.refills() + capsule_hint.refills();
  }
  EXPECT_GT(hits, refills);
}

// Nodes drifting in and out of reach of a limited query (empty answers), and unlimited queries
// on the same walk: the hint's cut is refilled around the empty and the far answers alike.
TEST(Coherent, WalksInAndOutOfReachEqualColdQueries) {
  const auto m = testing::make_bumpy_sphere(30, 40, 5.0, 0.1, 13);
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b) << b.error().message;
  std::mt19937 rng(67);
  std::uniform_real_distribution<double> step(0.0, 0.1);
  std::uint32_t empty = 0;
  for (int node = 0; node < 20; ++node) {
    const glm::dvec3 dir = testing::random_unit(rng);
    QueryHint limited;
    QueryHint unlimited;
    for (int s = 0; s < 80; ++s) {
      // Out from 4.5 mm to 6.5 mm from the centre and back, with a sideways jitter.
      const double r = 4.5 + 2.0 * (s < 40 ? s : 80 - s) / 40.0;
      const glm::dvec3 p = r * dir + step(rng) * testing::random_unit(rng);
      const auto cold = b->closest_point(p, 0.8);
      const auto warm = b->closest_point(p, 0.8, limited);
      ASSERT_EQ(cold.has_value(), warm.has_value()) << "node " << node << " step " << s;
      if (cold) expect_same(*cold, *warm);
      empty += cold ? 0u : 1u;
      const auto far_cold = b->closest_point(p);
      const auto far_warm = b->closest_point(p, ObbTree::kNoLimit, unlimited);
      ASSERT_TRUE(far_cold && far_warm);
      expect_same(*far_cold, *far_warm);
    }
    EXPECT_GT(unlimited.hits(), unlimited.refills());
  }
  EXPECT_GT(empty, 100u);  // the walk does leave the limited query's reach
}

// A hint filled on one tree is never trusted by another.
TEST(Coherent, HintFromAnotherTreeIsIgnored) {
  const auto small = testing::make_bumpy_sphere(12, 16, 2.0, 0.0, 1);
  const auto big = testing::make_bumpy_sphere(12, 16, 6.0, 0.0, 1);
  const TreeBuild a = ObbTree::build(small);
  const TreeBuild b = ObbTree::build(big);
  ASSERT_TRUE(a && b);
  QueryHint hint;
  const auto on_a = a->closest_point({0, 0, 0}, ObbTree::kNoLimit, hint);
  const auto on_b = b->closest_point({0, 0, 0}, ObbTree::kNoLimit, hint);
  ASSERT_TRUE(on_a && on_b);
  EXPECT_DOUBLE_EQ(on_b->distance_mm, b->closest_point({0, 0, 0})->distance_mm);
  EXPECT_GT(on_b->distance_mm, 5.0);
}

// Jumping far away invalidates the hint's cover, and the answer is still exact.
TEST(Coherent, JumpsFallBackToTheTree) {
  const auto m = testing::make_knot_tube(200, 12);
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b);
  std::mt19937 rng(71);
  QueryHint hint;
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 p = testing::random_surface_point(m, rng) + 0.5 * testing::random_unit(rng);
    const auto warm = b->closest_point(p, ObbTree::kNoLimit, hint);
    const auto cold = b->closest_point(p);
    ASSERT_TRUE(warm && cold);
    expect_same(*cold, *warm);
  }
}

}  // namespace
}  // namespace cathbox::collision

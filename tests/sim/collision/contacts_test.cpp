#include <array>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "test_meshes.hpp"

namespace cathbox::collision {
namespace {

using testing::near_rel;

TEST(SphereContacts, DeepestEqualsBruteForceOnEveryMesh) {
  for (const auto& named : testing::exactness_meshes()) {
    const auto& m = named.mesh;
    const TreeBuild b = ObbTree::build(m);
    ASSERT_TRUE(b) << b.error().message;
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> radius(0.05, 1.0);
    int touching = 0;
    for (const glm::dvec3& c : testing::query_points(m, 250, 1.5, 32)) {
      const double r = radius(rng);
      std::array<Contact, 16> out{};
      const std::size_t n = b->sphere_contacts(c, r, out);
      const double want = testing::nearest(m, c).distance;
      if (want >= r * (1.0 + 1e-9)) {
        EXPECT_EQ(n, 0u) << named.name;
        continue;
      }
      if (want > r * (1.0 - 1e-9)) continue;  // touching within rounding
      ASSERT_GE(n, 1u) << named.name;
      ++touching;
      // The global minimum is always among the contacts.
      std::size_t nearest = 0;
      for (std::size_t i = 1; i < n; ++i)
        if (glm::length(c - out[i].wall_point_mm) < glm::length(c - out[nearest].wall_point_mm)) nearest = i;
      const double dist0 = glm::length(c - out[nearest].wall_point_mm);
      EXPECT_TRUE(near_rel(dist0, want)) << named.name << " " << dist0 << " vs " << want;
      for (std::size_t i = 0; i < n; ++i) {
        EXPECT_GT(out[i].depth_mm, 0.0);
        if (i > 0) {
          EXPECT_LE(out[i].depth_mm, out[i - 1].depth_mm);
        }
        EXPECT_NEAR(glm::length(out[i].normal), 1.0, 1e-9);
        const double d = glm::length(c - out[i].wall_point_mm);
        EXPECT_LT(d, r);
        // depth = r - d on the lumen side, r + d beyond the wall
        EXPECT_TRUE(near_rel(out[i].depth_mm, r - d) || near_rel(out[i].depth_mm, r + d));
        const auto f = static_cast<std::size_t>(out[i].face);
        EXPECT_LT(testing::point_triangle_distance(out[i].wall_point_mm, testing::corner(m, f, 0),
                                                   testing::corner(m, f, 1), testing::corner(m, f, 2)),
                  1e-9);
        EXPECT_EQ(out[i].region, m.triangle_regions[f]);
      }
      if (named.closed) {
        // Pushing the centre along the deepest contact's normal by its depth clears that wall.
        const bool inside = testing::inside_by_parity(m, c);
        if (std::abs(want) > 1e-6) {
          EXPECT_TRUE(near_rel(out[nearest].depth_mm, inside ? r - want : r + want)) << named.name;
          // The normal points from the wall into the lumen.
          const glm::dvec3 toward = c - out[nearest].wall_point_mm;
          EXPECT_EQ(glm::dot(toward, out[nearest].normal) > 0.0, inside) << named.name;
        }
      }
    }
    EXPECT_GT(touching, 20) << named.name;
  }
}

// A sphere centred on a straight tube's axis touches the wall all around: one contact per
// local minimum, each on a different side.
TEST(SphereContacts, ReportsEveryLocalMinimum) {
  testing::TubeSpec spec;
  spec.centerline = [](double s) { return glm::dvec3{0.0, 0.0, 20.0 * s}; };
  spec.radius_mm = [](double) { return 1.0; };
  spec.rings = 41;
  spec.sides = 8;
  const auto m = testing::make_tube(spec);
  const TreeBuild b = ObbTree::build(m);
  ASSERT_TRUE(b);
  // Off-centre towards +x: touches only the +x side.
  std::array<Contact, 32> out{};
  std::size_t n = b->sphere_contacts({0.6, 0.0, 10.25}, 0.5, out);
  ASSERT_GE(n, 1u);
  for (std::size_t i = 0; i < n; ++i) EXPECT_GT(out[i].wall_point_mm.x, 0.5);
  EXPECT_LT(out[0].normal.x, -0.9);  // pushes back towards the axis
  // Centred with a radius larger than the wall distance: contacts on all 8 sides.
  n = b->sphere_contacts({0.0, 0.0, 10.25}, 1.0, out);
  ASSERT_GE(n, 8u);
  int sides_hit[8] = {};
  for (std::size_t i = 0; i < n; ++i) {
    const double a = std::atan2(out[i].wall_point_mm.y, out[i].wall_point_mm.x);
    const int k = static_cast<int>(std::floor(a / (2.0 * 3.14159265358979 / 8.0)) + 8) % 8;
    sides_hit[k] = 1;
    EXPECT_NEAR(glm::length(glm::dvec3(out[i].wall_point_mm.x, out[i].wall_point_mm.y, 0.0)), std::cos(3.14159265358979 / 8.0), 1e-2);
  }
  int total = 0;
  for (int s : sides_hit) total += s;
  EXPECT_GE(total, 7);
  // A span of one keeps the deepest only.
  EXPECT_EQ(b->sphere_contacts({0.0, 0.0, 10.25}, 1.0, std::span<Contact>(out.data(), 1)), 1u);
}

TEST(CapsuleContacts, DeepestEqualsBruteForce) {
  for (const auto& named : testing::exactness_meshes()) {
    const auto& m = named.mesh;
    const TreeBuild b = ObbTree::build(m);
    ASSERT_TRUE(b) << b.error().message;
    std::mt19937 rng(41);
    std::uniform_real_distribution<double> radius(0.05, 0.6);
    std::uniform_real_distribution<double> length(0.0, 2.0);
    int touching = 0;
    for (const glm::dvec3& p : testing::query_points(m, 120, 1.0, 42)) {
      const double r = radius(rng);
      const glm::dvec3 q = p + length(rng) * testing::random_unit(rng);
      std::array<Contact, 16> out{};
      const std::size_t n = b->capsule_contacts(p, q, r, out);
      const double want = testing::segment_distance(m, p, q);
      if (want >= r * (1.0 + 1e-6)) {
        EXPECT_EQ(n, 0u);
        continue;
      }
      if (want > r * (1.0 - 1e-6)) continue;
      ASSERT_GE(n, 1u) << named.name;
      ++touching;
      double nearest = 1e30;
      for (std::size_t i = 0; i < n; ++i)
        nearest = std::min(nearest, glm::length(p + out[i].segment_t * (q - p) - out[i].wall_point_mm));
      EXPECT_TRUE(near_rel(nearest, want, 1e-6, 1e-7)) << named.name << " " << nearest << " vs " << want;
      for (std::size_t i = 0; i < n; ++i) {
        EXPECT_GE(out[i].segment_t, 0.0);
        EXPECT_LE(out[i].segment_t, 1.0);
        EXPECT_GT(out[i].depth_mm, 0.0);
        EXPECT_NEAR(glm::length(out[i].normal), 1.0, 1e-9);
      }
    }
    EXPECT_GT(touching, 10) << named.name;
  }
}

TEST(Contacts, BadInputGivesNothing) {
  const TreeBuild b = ObbTree::build(testing::make_bumpy_sphere(10, 12, 3.0, 0.0, 1));
  ASSERT_TRUE(b);
  const double nan = testing::kNaN;
  const double inf = testing::kInf;
  std::array<Contact, 4> out{};
  QueryHint hint;
  EXPECT_EQ(b->sphere_contacts({nan, 0, 0}, 1.0, out), 0u);
  EXPECT_EQ(b->sphere_contacts({0, 0, 0}, nan, out), 0u);
  EXPECT_EQ(b->sphere_contacts({0, 0, 0}, -1.0, out), 0u);
  EXPECT_EQ(b->sphere_contacts({0, 0, 0}, inf, out), 0u);
  EXPECT_EQ(b->sphere_contacts({0, 0, 2.9}, 1.0, std::span<Contact>{}), 0u);
  EXPECT_EQ(b->capsule_contacts({0, 0, 0}, {inf, 0, 0}, 1.0, out), 0u);
  EXPECT_EQ(b->capsule_contacts({0, 0, 0}, {1, 0, 0}, nan, out, hint), 0u);
  EXPECT_EQ(b->sphere_contacts({nan, 0, 0}, 1.0, out, hint), 0u);
  // A huge sphere touching everything still answers (with at least the deepest contact).
  EXPECT_GE(b->sphere_contacts({0, 0, 0}, 100.0, out), 1u);
}

}  // namespace
}  // namespace cathbox::collision

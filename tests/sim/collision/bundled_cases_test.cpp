// Exactness on the bundled vessel cases (cases/*.hclm through the vessel mesher): closest
// points, signs, contacts and ray casts equal brute force over all triangles.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "test_meshes.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::collision {
namespace {

using testing::near_rel;

struct BundledCase {
  const char* file;
  int level;
};

class BundledCaseTest : public ::testing::TestWithParam<BundledCase> {
 protected:
  void SetUp() override {
    vessel::MeshOptions options;
    options.subdivision_level = GetParam().level;
    auto loaded = vessel::load_surface_mesh(std::string(CATHBOX_SOURCE_DIR) + "/cases/" + GetParam().file, options);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    mesh_ = std::move(*loaded);
    TreeBuild b = ObbTree::build(mesh_);
    ASSERT_TRUE(b) << b.error().message;
    tree_.emplace(std::move(*b));
  }
  vessel::SurfaceMesh mesh_;
  std::optional<ObbTree> tree_;
};

TEST_P(BundledCaseTest, TreeFollowsRegionsAndMeshIsClosed) {
  const TreeStats& s = tree_->stats();
  EXPECT_TRUE(s.closed);
  EXPECT_TRUE(s.consistently_oriented);
  EXPECT_EQ(s.degenerate_dropped, 0u);
  EXPECT_EQ(s.triangles, mesh_.triangle_count());
  std::vector<vessel::FaceRegion> distinct;
  for (const auto& r : mesh_.triangle_regions)
    if (std::find(distinct.begin(), distinct.end(), r) == distinct.end()) distinct.push_back(r);
  EXPECT_EQ(s.regions, distinct.size());
}

TEST_P(BundledCaseTest, ClosestPointAndSignEqualBruteForce) {
  int index = 0;
  for (const glm::dvec3& p : testing::query_points(mesh_, 120, 2.0, 81)) {
    const testing::BruteNearest want = testing::nearest(mesh_, p);
    const auto got = tree_->closest_point(p);
    ASSERT_TRUE(got);
    EXPECT_TRUE(near_rel(got->distance_mm, want.distance)) << got->distance_mm << " vs " << want.distance;
    EXPECT_EQ(got->region, mesh_.triangle_regions[static_cast<std::size_t>(got->face)]);
    if (index++ % 3 == 0 && std::abs(got->signed_distance_mm) > 1e-6) {
      EXPECT_EQ(got->signed_distance_mm < 0.0, testing::inside_by_parity(mesh_, p));
    }
  }
}

TEST_P(BundledCaseTest, SphereContactsAndRaysEqualBruteForce) {
  std::mt19937 rng(83);
  std::uniform_real_distribution<double> radius(0.05, 0.8);
  QueryHint hint;
  for (const glm::dvec3& c : testing::query_points(mesh_, 60, 1.0, 84)) {
    const double r = radius(rng);
    const double want = testing::nearest(mesh_, c).distance;
    std::array<Contact, 8> out{};
    const std::size_t n = tree_->sphere_contacts(c, r, out, hint);
    if (want >= r * (1.0 + 1e-9)) {
      EXPECT_EQ(n, 0u);
    } else if (want <= r * (1.0 - 1e-9)) {
      ASSERT_GE(n, 1u);
      double nearest = 1e30;
      for (std::size_t i = 0; i < n; ++i) nearest = std::min(nearest, glm::length(c - out[i].wall_point_mm));
      EXPECT_TRUE(near_rel(nearest, want));
    }
    const glm::dvec3 dir = testing::random_unit(rng);
    const auto hit = tree_->ray_cast(c, dir);
    const auto brute = testing::first_hit(mesh_, c, dir);
    ASSERT_EQ(hit.has_value(), brute.has_value());
    if (hit) {
      EXPECT_TRUE(near_rel(hit->t, *brute, 1e-6, 1e-12));
    }
  }
}

// Tool nodes walking near the wall in steps of up to 0.1 mm, on meshes big enough that the
// hints' cuts fill up: coherent closest points (unlimited and within 0.7 mm) and sphere contacts
// equal the cold ones exactly.
TEST_P(BundledCaseTest, CoherentWalksEqualColdQueries) {
  std::mt19937 rng(87);
  std::uniform_real_distribution<double> step(0.0, 0.1);
  std::uint32_t hits = 0;
  std::uint32_t refills = 0;
  for (glm::dvec3 p : testing::query_points(mesh_, 24, 2.0, 88)) {
    QueryHint far_hint;
    QueryHint probe_hint;
    QueryHint sphere_hint;
    for (int s = 0; s < 40; ++s) {
      p += step(rng) * testing::random_unit(rng);
      const auto cold = tree_->closest_point(p);
      const auto warm = tree_->closest_point(p, ObbTree::kNoLimit, far_hint);
      ASSERT_TRUE(cold && warm);
      EXPECT_DOUBLE_EQ(cold->distance_mm, warm->distance_mm);
      EXPECT_NEAR(glm::length(cold->normal - warm->normal), 0.0, 1e-9);
      const auto probe = tree_->closest_point(p, 0.7, probe_hint);
      ASSERT_EQ(probe.has_value(), cold->distance_mm <= 0.7);
      if (probe) {
        EXPECT_DOUBLE_EQ(probe->distance_mm, cold->distance_mm);
      }
      std::array<Contact, 8> a{}, b{};
      const std::size_t na = tree_->sphere_contacts(p, 0.5, a);
      const std::size_t nb = tree_->sphere_contacts(p, 0.5, b, sphere_hint);
      ASSERT_EQ(na, nb);
      for (std::size_t i = 0; i < na; ++i) EXPECT_NEAR(a[i].depth_mm, b[i].depth_mm, 1e-12);
    }
    hits += far_hint.hits() + probe_hint.hits() + sphere_hint.hits();
    refills += far_hint.refills() + probe_hint.refills() + sphere_hint.refills();
  }
  EXPECT_GT(hits, 4 * refills);
}

// The fused sphere query (contacts and the closest point in one pass) along walks of tool
// nodes touching the wall (radius 0.2-1 mm, steps of 0.002-0.4 mm): its closest point equals the
// cold closest_point's (distance, sign, point, pseudo-normal) whenever the wall is closer than
// the radius and is empty otherwise, and its contacts equal the two-query answer's.
TEST_P(BundledCaseTest, FusedSphereQueryGivesTheClosestPointAndTheContacts) {
  std::mt19937 rng(91);
  std::uniform_real_distribution<double> small(0.002, 0.05);
  std::uniform_real_distribution<double> lurch(0.05, 0.4);
  std::uniform_real_distribution<double> radius_of(0.2, 1.0);
  std::uniform_int_distribution<int> every(0, 9);
  int found = 0, empty = 0;
  for (glm::dvec3 p : testing::query_points(mesh_, 40, 0.0, 92)) {
    const double radius = radius_of(rng);
    const auto start = tree_->closest_point(p);
    ASSERT_TRUE(start);
    p = start->point_mm - start->normal * (radius - 0.1);  // touching the wall from the lumen
    QueryHint hint;
    QueryHint plain_hint;
    for (int s = 0; s < 50; ++s) {
      p += (every(rng) == 0 ? lurch(rng) : small(rng)) * testing::random_unit(rng);
      std::array<Contact, 3> a{}, b{};
      std::optional<ClosestPoint> nearest;
      const std::size_t na = tree_->sphere_contacts(p, radius, a, hint, nearest);
      const std::size_t nb = tree_->sphere_contacts(p, radius, b, plain_hint);
      const auto cold = tree_->closest_point(p);
      ASSERT_TRUE(cold);
      ASSERT_EQ(na, nb);
      ASSERT_EQ(nearest.has_value(), cold->distance_mm < radius);
      ASSERT_EQ(nearest.has_value(), na > 0);
      for (std::size_t i = 0; i < na; ++i) {
        EXPECT_NEAR(a[i].depth_mm, b[i].depth_mm, 1e-12);
        EXPECT_NEAR(glm::length(a[i].wall_point_mm - b[i].wall_point_mm), 0.0, 1e-9);
        EXPECT_NEAR(glm::length(a[i].normal - b[i].normal), 0.0, 1e-9);
      }
      if (!nearest) {
        ++empty;
        continue;
      }
      ++found;
      EXPECT_DOUBLE_EQ(nearest->distance_mm, cold->distance_mm);
      EXPECT_DOUBLE_EQ(nearest->signed_distance_mm, cold->signed_distance_mm);
      EXPECT_NEAR(glm::length(nearest->point_mm - cold->point_mm), 0.0, 1e-9);
      EXPECT_NEAR(glm::length(nearest->normal - cold->normal), 0.0, 1e-9);
      if (nearest->face == cold->face) {
        EXPECT_EQ(nearest->region, cold->region);
        EXPECT_EQ(nearest->feature, cold->feature);
      }
    }
  }
  EXPECT_GT(found, 400);  // most walks stay on the wall; some leave it
  EXPECT_GT(empty, 10);
  std::array<Contact, 3> none{};
  QueryHint hint;
  std::optional<ClosestPoint> nearest = ClosestPoint{};
  EXPECT_EQ(tree_->sphere_contacts(glm::dvec3(std::nan("")), 1.0, none, hint, nearest), 0u);
  EXPECT_FALSE(nearest);
}

std::string case_name(const ::testing::TestParamInfo<BundledCase>& info) {
  std::string name = info.param.file;
  name = name.substr(0, name.find('.'));
  return name + "_L" + std::to_string(info.param.level);
}

INSTANTIATE_TEST_SUITE_P(Cases, BundledCaseTest,
                         ::testing::Values(BundledCase{"neuro.hclm", 1}, BundledCase{"neuro_aneurysm.hclm", 1},
                                           BundledCase{"neuro_small_aneurysm.hclm", 1}, BundledCase{"y_bifurcation.hclm", 2}, BundledCase{"seed_catheter.hclm", 3}),
                         case_name);

}  // namespace
}  // namespace cathbox::collision

namespace cathbox::collision {
namespace {

// A tree built with a TreeCache is the tree built afresh: the bundled stenosis case, then the
// same model with one segment widened (as a balloon does): the regions whose triangles did not
// change come from the cache, the others are built again, and every answer (closest point with
// its face and feature, contacts, rays) equals the fresh tree's at random points; built again
// with the cache, every region is reused.
TEST(TreeCache, ReusedRegionsGiveTheTreeAFreshBuildGives) {
  vessel::HclmReadResult read = vessel::load_hclm(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_stenosis.hclm");
  ASSERT_TRUE(read.ok());
  vessel::VesselModel widened = read.model;
  ASSERT_GT(widened.segments.size(), 20u);
  vessel::Segment& seg = widened.segments[19];
  for (std::size_t i = 3; i + 3 < seg.points.size() && i < 12; ++i) seg.points[i].radius_mm = std::max(seg.points[i].radius_mm, 2.0);
  vessel::VesselSurface before = vessel::build_vessel_surface(read.model);
  vessel::VesselSurface after = vessel::build_vessel_surface(widened);
  ASSERT_TRUE(before.ok() && after.ok());

  TreeCache cache;
  ASSERT_TRUE(ObbTree::build(before.mesh, {}, cache));
  EXPECT_EQ(cache.reused_regions(), 0u);
  TreeBuild cached = ObbTree::build(after.mesh, {}, cache);
  ASSERT_TRUE(cached);
  EXPECT_GT(cache.reused_regions(), 10u);
  EXPECT_GT(cache.built_regions(), 0u);
  TreeBuild fresh = ObbTree::build(after.mesh);
  ASSERT_TRUE(fresh);
  TreeBuild again = ObbTree::build(after.mesh, {}, cache);
  ASSERT_TRUE(again);
  EXPECT_EQ(cache.built_regions(), 0u) << "the same mesh again: every region from the cache";

  EXPECT_EQ(cached->stats().wide_nodes, fresh->stats().wide_nodes);
  EXPECT_EQ(cached->stats().leaves, fresh->stats().leaves);
  EXPECT_EQ(cached->stats().depth, fresh->stats().depth);
  // Bit for bit: nodes, leaf blocks (copied for the reused regions' leaves), face normals and
  // corner angles (taken from the cache for their triangles), pseudo-normals, neighbours.
  EXPECT_EQ(cached->content_hash(), fresh->content_hash());
  EXPECT_EQ(again->content_hash(), fresh->content_hash());
  EXPECT_NE(cached->content_hash(), ObbTree::build(before.mesh)->content_hash());
  glm::vec3 lo(1e30F), hi(-1e30F);
  for (const glm::vec3& p : after.mesh.positions_mm) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 3000; ++i) {
    // Half the points near the wall (a vertex plus a small offset), half anywhere.
    glm::dvec3 p;
    if (i % 2 == 0) {
      const glm::vec3 v = after.mesh.positions_mm[static_cast<std::size_t>(u(rng) * (after.mesh.positions_mm.size() - 1))];
      p = glm::dvec3(v) + glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    } else {
      p = glm::dvec3(lo) + glm::dvec3(u(rng), u(rng), u(rng)) * glm::dvec3(hi - lo);
    }
    for (const ObbTree* t : {&*cached, &*again}) {
      const auto a = t->closest_point(p);
      const auto b = fresh->closest_point(p);
      ASSERT_EQ(a.has_value(), b.has_value());
      ASSERT_EQ(a->face, b->face) << i;
      ASSERT_EQ(a->point_mm, b->point_mm) << i;
      ASSERT_EQ(a->signed_distance_mm, b->signed_distance_mm) << i;
      ASSERT_EQ(a->normal, b->normal) << i;
      ASSERT_EQ(a->feature, b->feature) << i;
      std::array<Contact, 4> ca{}, cb{};
      const std::size_t na = t->sphere_contacts(p, 0.8, ca);
      ASSERT_EQ(na, fresh->sphere_contacts(p, 0.8, cb)) << i;
      for (std::size_t k = 0; k < na; ++k) ASSERT_EQ(ca[k].wall_point_mm, cb[k].wall_point_mm) << i;
      const glm::dvec3 dir(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      const auto ra = t->ray_cast(p, dir, 50.0);
      const auto rb = fresh->ray_cast(p, dir, 50.0);
      ASSERT_EQ(ra.has_value(), rb.has_value()) << i;
      if (ra) {
        ASSERT_EQ(ra->t, rb->t) << i;
      }
    }
  }
}

// The incremental path never takes a changed region from the cache: one vertex moved by one
// float step (every triangle around it changes by the least a float can) gives, built with the
// cache, the tree a fresh build gives (bit for bit, and the same answers at that vertex), not
// the last one; the regions of the triangles around it are built again and the others reused.
TEST(TreeCache, ARegionWhoseTrianglesChangedByOneFloatStepIsBuiltAgain) {
  vessel::HclmReadResult read = vessel::load_hclm(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_stenosis.hclm");
  ASSERT_TRUE(read.ok());
  vessel::VesselSurface before = vessel::build_vessel_surface(read.model);
  ASSERT_TRUE(before.ok());
  const vessel::SurfaceMesh& mesh = before.mesh;
  for (const std::size_t pick : {mesh.triangles.size() / 3, mesh.triangles.size() / 2 + 1}) {
    const std::uint32_t v = mesh.triangles[pick];
    vessel::SurfaceMesh moved = mesh;
    moved.positions_mm[v].x = std::nextafter(moved.positions_mm[v].x, 1e9F);
    std::set<std::pair<int, std::int32_t>> touched;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
      for (int k = 0; k < 3; ++k)
        if (mesh.triangles[3 * t + k] == v) touched.insert({static_cast<int>(mesh.triangle_regions[t].kind), mesh.triangle_regions[t].id});

    TreeCache cache;
    TreeBuild old = ObbTree::build(mesh, {}, cache);
    ASSERT_TRUE(old);
    const std::size_t regions = cache.built_regions();
    TreeBuild cached = ObbTree::build(moved, {}, cache);
    TreeBuild fresh = ObbTree::build(moved);
    ASSERT_TRUE(cached && fresh);
    EXPECT_EQ(cache.built_regions(), touched.size()) << "vertex " << v;
    EXPECT_EQ(cache.reused_regions(), regions - touched.size()) << "vertex " << v;
    EXPECT_EQ(cached->content_hash(), fresh->content_hash()) << "vertex " << v;
    EXPECT_NE(cached->content_hash(), old->content_hash()) << "vertex " << v;
    const glm::dvec3 at = glm::dvec3(moved.positions_mm[v]) + glm::dvec3(0.01, -0.02, 0.015);
    const auto a = cached->closest_point(at);
    const auto b = fresh->closest_point(at);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->point_mm, b->point_mm);
    EXPECT_EQ(a->face, b->face);
    EXPECT_EQ(a->normal, b->normal);
  }
}

}  // namespace
}  // namespace cathbox::collision

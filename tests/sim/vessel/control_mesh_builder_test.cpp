#include "vessel/control_mesh_builder.hpp"

#include <cmath>
#include <limits>
#include <numeric>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "vessel/case_generator.hpp"
#include "vessel/centerline_smoother.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_analysis.hpp"
#include "vessel/subdivision.hpp"

namespace cathbox::vessel {
namespace {

ControlMeshResult build(const VesselModel& model, const MeshOptions& options) {
  const VesselGraph graph(model);
  return build_control_mesh(
      smooth_centerlines(model, graph, options.smoothing_passes, options.trim_at_junctions, options.smoothing), graph,
      options);
}

// The thesis' count (3.2.3.2): m segments of k_i nodes and n bifurcations give 4 sum k_i points
// and 4 sum (k_i - 1) + 7 n faces, with M = 4, open ends and a ring per HCLM point.
void expect_thesis_counts(const VesselModel& model) {
  MeshOptions options;
  options.ring_points = 4;
  options.caps = false;
  options.ring_placement = RingPlacement::kPerPoint;
  const ControlMeshResult built = build(model, options);
  ASSERT_TRUE(built.ok()) << built.error().message;
  const VesselGraph graph(model);
  std::size_t sum_k = 0;
  std::size_t sum_k1 = 0;
  for (const Segment& s : model.segments) {
    sum_k += s.points.size();
    sum_k1 += s.points.size() - 1;
  }
  std::size_t bifurcations = 0;
  for (const Junction& j : graph.junctions()) {
    ASSERT_EQ(j.ends.size(), 3u) << "not a plain bifurcation model";
    ++bifurcations;
  }
  EXPECT_EQ(built->vertex_count(), 4 * sum_k);
  EXPECT_EQ(built->face_count(), 4 * sum_k1 + 7 * bifurcations);
  for (int size : built->face_sizes) EXPECT_EQ(size, 4);  // all quads, as in the thesis
}

TEST(ControlMeshBuilder, ReproducesTheThesisCountsForAYBifurcation) {
  expect_thesis_counts(CaseGenerator::y_bifurcation());
}

TEST(ControlMeshBuilder, ReproducesTheThesisCountsForRandomBinaryTrees) {
  RandomTreeOptions options;
  options.segments = 41;
  options.trifurcation_chance = 0.0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) expect_thesis_counts(CaseGenerator::random_tree(seed, options));
}

TEST(ControlMeshBuilder, WithoutTrimmingRingsSitAtEveryHclmPointAsInTheThesis) {
  // Children that start two parent radii beyond the parent's end (the "near" of the HCLM rule)
  // leave the junction room without trimming: every ring is at its HCLM point.
  VesselModel model = CaseGenerator::y_bifurcation();
  for (std::size_t c = 1; c <= 2; ++c) {
    auto& pts = model.segments[c].points;
    const glm::dvec3 start = pts.front().pos_mm;
    std::erase_if(pts, [&](const CenterlinePoint& p) { return glm::length(p.pos_mm - start) < 6.0; });
  }
  ASSERT_TRUE(validate_model(model).empty());
  MeshOptions options;
  options.ring_points = 4;
  options.caps = false;
  options.trim_at_junctions = false;
  options.compensate_shrink = false;
  options.smoothing_passes = 0;
  const ControlMeshResult built = build(model, options);
  ASSERT_TRUE(built.ok()) << built.error().message;
  std::size_t ring = 0;
  for (const Segment& s : model.segments) {
    for (const CenterlinePoint& p : s.points) {
      EXPECT_NEAR(glm::length(built->rings[ring].center_mm - p.pos_mm), 0.0, 1e-9);
      EXPECT_NEAR(built->rings[ring].control_radius_mm, p.radius_mm, 1e-12);
      ++ring;
    }
  }
  EXPECT_EQ(built->face_count(), 4 * (model.point_count() - 3) + 7);
  // Children starting exactly at the parent's end leave no room: the spherical-hull fallback
  // meshes that junction (and names it); without it, a clean error.
  const ControlMeshResult fallback = build(CaseGenerator::y_bifurcation(), options);
  ASSERT_TRUE(fallback.ok()) << fallback.error().message;
  ASSERT_EQ(fallback->fallback_junctions.size(), 1u);
  EXPECT_EQ(fallback->fallback_junctions[0].junction, 0u);
  options.junction_fallback = false;
  const ControlMeshResult crowded = build(CaseGenerator::y_bifurcation(), options);
  EXPECT_FALSE(crowded.ok());
  EXPECT_NE(crowded.error().message.find("junction 0"), std::string::npos) << crowded.error().message;
}

TEST(ControlMeshBuilder, RingsFollowTheCenterlineWithCompensatedRadius) {
  const VesselModel model = CaseGenerator::y_bifurcation();
  for (int m : {4, 8, 16}) {
    MeshOptions options;
    options.ring_points = m;
    const ControlMeshResult built = build(model, options);
    ASSERT_TRUE(built.ok()) << built.error().message;
    for (const Ring& ring : built->rings) {
      EXPECT_NEAR(ring.control_radius_mm * tube_shrink_ratio(m), ring.radius_mm, 1e-12);
      for (int k = 0; k < m; ++k) {
        const glm::dvec3 p = built->positions_mm[ring.first_vertex + static_cast<std::uint32_t>(k)];
        EXPECT_NEAR(glm::length(p - ring.center_mm), ring.control_radius_mm, 1e-9);
        EXPECT_NEAR(glm::dot(p - ring.center_mm, ring.tangent), 0.0, 1e-9);
      }
    }
  }
}

TEST(ControlMeshBuilder, ShrinkRatioMatchesTheCubicBSplineOfARegularPolygon) {
  EXPECT_NEAR(tube_shrink_ratio(4), 0.5 * (2.0 / 3.0 + 0.6481), 1e-4);
  EXPECT_NEAR(tube_shrink_ratio(8), 0.9019, 1e-3);
  EXPECT_GT(tube_shrink_ratio(16), 0.97);
  EXPECT_LT(tube_shrink_ratio(16), 1.0);
}

TEST(ControlMeshBuilder, JunctionTemplateHandlesAnyNumberOfBranches) {
  // A star: one parent and 2..6 children spread on a cone; the control mesh must be a closed
  // manifold with consistent orientation for every count.
  for (int children = 2; children <= 6; ++children) {
    std::string text = "s " + std::to_string(children + 1) + "\ng 1\np 0\nc " + std::to_string(children);
    for (int c = 0; c < children; ++c) text += " " + std::to_string(c + 2);
    text += "\nn 11\n";
    for (int i = 0; i <= 10; ++i) text += "v 0 0 " + std::to_string(3 * i) + " 2\n";
    for (int c = 0; c < children; ++c) {
      const double az = 2.0 * 3.14159265358979 * c / children;
      const glm::dvec3 dir = glm::normalize(glm::dvec3(std::cos(az), std::sin(az), 0.9));
      text += "g " + std::to_string(c + 2) + "\np 1 1\nc 0\nn 11\n";
      for (int i = 0; i <= 10; ++i) {
        const glm::dvec3 p = glm::dvec3(0, 0, 30) + 3.0 * i * dir;
        text += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + " 1.2\n";
      }
    }
    const HclmReadResult read = read_hclm(text);
    ASSERT_TRUE(read.ok()) << read.errors.front().to_string();
    for (int m : {4, 6, 8}) {
      MeshOptions options;
      options.ring_points = m;
      const ControlMeshResult built = build(read.model, options);
      ASSERT_TRUE(built.ok()) << children << " children, M " << m << ": " << built.error().message;
      const SurfaceMeshResult flat = subdivide(*built, 0);
      ASSERT_TRUE(flat.ok());
      const MeshAnalysis a = analyze_mesh(*flat);
      EXPECT_TRUE(a.closed() && a.manifold() && a.consistently_oriented()) << children << " children, M " << m;
      EXPECT_EQ(a.euler_characteristic, 2);
      EXPECT_GT(a.signed_volume_mm3, 0.0);
      // Junction faces: quads where a perfect pairing exists, at most a few triangles otherwise.
      std::size_t junction_triangles = 0;
      for (std::size_t f = 0; f < built->face_count(); ++f) {
        if (built->face_regions[f].kind == RegionKind::kJunction && built->face_sizes[f] == 3) ++junction_triangles;
      }
      EXPECT_LE(junction_triangles, 2u) << children << " children, M " << m;
    }
  }
}

TEST(ControlMeshBuilder, OverlappingBranchesAreAnErrorNotACrashWithoutTheFallback) {
  // A child folding straight back along its parent cannot get a hull junction; without the
  // spherical-hull fallback (junction_fallback_test.cpp) that is an error naming the junction.
  const HclmReadResult read = read_hclm(
      "s 2\ng 1\np 0\nc 1 2\nn 3\nv 0 0 0 2\nv 0 0 1 2\nv 0 0 2 2\n"
      "g 2\np 1 1\nc 0\nn 3\nv 0 0 2 2\nv 0 0.01 1 2\nv 0 0.02 0 2\n");
  ASSERT_TRUE(read.ok()) << read.errors.front().to_string();
  MeshOptions options;
  options.junction_fallback = false;
  const ControlMeshResult built = build(read.model, options);
  EXPECT_FALSE(built.ok());
  EXPECT_NE(built.error().message.find("junction 0 (segments 1 2)"), std::string::npos) << built.error().message;
  const ControlMeshResult fallback = build(read.model, MeshOptions{});
  ASSERT_TRUE(fallback.ok()) << fallback.error().message;
  ASSERT_EQ(fallback->fallback_junctions.size(), 1u);
  EXPECT_EQ(fallback->fallback_junctions[0].what, "junction 0 (segments 1 2): branches overlap (a ring is not on the junction's hull)");
}

// The mesher never casts a non-finite or overflowing value (UBSan found a NaN converted to int
// for a model with a point at 5.6e214 mm): a model that did not come through a reader is refused.
TEST(ControlMeshBuilder, RefusesPointsOutsideTheBodysRange) {
  VesselModel model = CaseGenerator::y_bifurcation();
  model.segments[1].points[1].pos_mm.z = 5.6e214;
  const ControlMeshResult far = build(model, MeshOptions{});
  ASSERT_FALSE(far.ok());
  // (build() smooths first, so the point has moved, and its step normal to the chord spreads the
  // overflow into its other coordinates, but it is still far outside)
  EXPECT_NE(far.error().message.find("segment 2 point 1: "), std::string::npos) << far.error().message;
  EXPECT_NE(far.error().message.find("e+21"), std::string::npos) << far.error().message;
  EXPECT_NE(far.error().message.find(" mm is outside ±2000 mm"), std::string::npos) << far.error().message;
  model.segments[1].points[1].pos_mm.z = std::numeric_limits<double>::quiet_NaN();
  const ControlMeshResult nan = build(model, MeshOptions{});
  ASSERT_FALSE(nan.ok());
  EXPECT_NE(nan.error().message.find("z is not finite"), std::string::npos) << nan.error().message;
}

TEST(ControlMeshBuilder, RejectsBadRingSizes) {
  MeshOptions options;
  options.ring_points = 2;
  EXPECT_FALSE(build(CaseGenerator::y_bifurcation(), options).ok());
}

TEST(ControlMeshBuilder, TagsEveryFaceWithItsSegmentJunctionOrCap) {
  const VesselModel model = CaseGenerator::y_bifurcation();
  MeshOptions options;
  options.ring_placement = RingPlacement::kPerPoint;
  const ControlMeshResult built = build(model, options);
  ASSERT_TRUE(built.ok());
  std::size_t segment = 0, junction = 0, cap = 0;
  for (const FaceRegion& r : built->face_regions) {
    if (r.kind == RegionKind::kSegment) ++segment;
    if (r.kind == RegionKind::kJunction) ++junction;
    if (r.kind == RegionKind::kCap) ++cap;
  }
  std::size_t sum_k1 = 0;
  for (const Segment& s : model.segments) sum_k1 += s.points.size() - 1;
  EXPECT_EQ(segment, 8 * sum_k1);
  EXPECT_EQ(junction, 8u * 3u / 2u + 1u);  // k M / 2 + k - 2 quads
  EXPECT_EQ(cap, 3u * (8u + 1u));           // a band of M quads and one M-gon per free end
}

}  // namespace
}  // namespace cathbox::vessel

#pragma once
// Exact (double) distance primitives between points, segments, rays and one triangle.
#include <cstdint>
#include <optional>

#include <glm/vec3.hpp>

#include "collision/closest_point.hpp"
#include "collision/segment_pair.hpp"

namespace cathbox::collision::detail {

struct TriangleFeature {
  FeatureKind kind = FeatureKind::kFace;
  std::uint8_t index = 0;  // edge k runs from corner k to corner (k + 1) % 3
};

struct PointOnTriangle {
  glm::dvec3 point{0.0};
  TriangleFeature feature{};
};

// Closest point of triangle abc to p, and the feature it lies on (Voronoi regions of the
// corners, then edges, then the face).
[[nodiscard]] PointOnTriangle closest_on_triangle(const glm::dvec3& p, const glm::dvec3& a,
                                                  const glm::dvec3& b, const glm::dvec3& c);

[[nodiscard]] double point_triangle_distance_sq(const glm::dvec3& p, const glm::dvec3& a,
                                                const glm::dvec3& b, const glm::dvec3& c);

using collision::closest_segment_segment;
using collision::SegmentPair;

struct SegmentOnTriangle {
  double segment_t = 0.0;  // parameter of the closest point on p0-p1
  double distance_sq = 0.0;
  PointOnTriangle on_triangle;
};

[[nodiscard]] SegmentOnTriangle closest_segment_triangle(const glm::dvec3& p0,
                                                         const glm::dvec3& p1,
                                                         const glm::dvec3& a,
                                                         const glm::dvec3& b,
                                                         const glm::dvec3& c);

// Ray origin + t * dir against triangle abc (both sides); the hit parameter, if any, in [0, max_t].
[[nodiscard]] std::optional<double> ray_triangle(const glm::dvec3& origin, const glm::dvec3& dir,
                                                 const glm::dvec3& a, const glm::dvec3& b,
                                                 const glm::dvec3& c, double max_t);

}  // namespace cathbox::collision::detail

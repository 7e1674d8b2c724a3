#pragma once
// The queries' small shared pieces: limits, float lanes of a point, prefetch, a four-lane sort,
// the pseudo-normals of a triangle's features.
// Included by obb_tree.cpp only: the queries compile as one translation unit, as they did when
// they were one file, so that the compiler inlines across these parts exactly as before (the
// float kernels are built with -ffp-contract=fast, whose fused multiply-adds follow inlining).
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>

#include "collision/obb_tree.hpp"
#include "float_bounds.hpp"
#include "kernels.hpp"
#include "tree_data.hpp"
#include "triangle_geometry.hpp"

namespace cathbox::collision {

using detail::PointLanes;
using detail::TreeData;
using detail::v4f;

namespace {

constexpr int kStackSize = 256 + QueryHint::kSlots;  // > hint slots + 3 * max wide depth + 4
constexpr int kMaxCandidates = 128;   // triangles touching one sphere or capsule
constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

float slack_for(const TreeData& d, const glm::dvec3& p) { return detail::slack_for(d.scale_mm, p); }
using detail::threshold_sq;

PointLanes lanes_of(const glm::dvec3& p) {
  return detail::splat_point(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
}

// Starts loading a node or block that is about to be tested (their misses dominate).
template <typename T>
CATHBOX_COLLISION_INLINE void prefetch(const T& object) {
  const char* p = reinterpret_cast<const char*>(&object);
  for (std::size_t line = 0; line < sizeof(T); line += 64) __builtin_prefetch(p + line);
}

// Lane order by ascending value.
CATHBOX_COLLISION_INLINE void sort4(v4f values, float (&v)[4], int (&order)[4]) {
  std::memcpy(v, &values, sizeof v);
  for (int i = 0; i < 4; ++i) order[i] = i;
  for (int i = 1; i < 4; ++i) {
    const int o = order[i];
    int j = i;
    for (; j > 0 && v[order[j - 1]] > v[o]; --j) order[j] = order[j - 1];
    order[j] = o;
  }
}

// Outward pseudo-normal of a feature of a mesh triangle: the face normal, the normalised
// sum of the two face normals at an edge, the angle-weighted vertex normal.
glm::dvec3 pseudo_normal(const TreeData& d, std::int32_t face, detail::TriangleFeature feature) {
  const auto f = static_cast<std::size_t>(face);
  switch (feature.kind) {
    case FeatureKind::kFace:
      return d.face_normals[f];
    case FeatureKind::kEdge: {
      const std::int32_t opp = d.opposite[3 * f + feature.index];
      glm::dvec3 n = d.face_normals[f];
      if (opp >= 0) n += d.face_normals[static_cast<std::size_t>(opp)];
      const double len = glm::length(n);
      return len > 0.0 ? n / len : d.face_normals[f];
    }
    case FeatureKind::kVertex:
      return d.vertex_normals[d.triangles[3 * f + feature.index]];
  }
  return d.face_normals[f];
}

// The answer of a closest-point search whose nearest triangle is `face` (q on it, at squared
// distance dsq from p); block_normal: the unit normal its leaf block stores (0 for slivers).
ClosestPoint closest_from(const TreeData& d, const glm::dvec3& p, const detail::PointOnTriangle& q, double dsq,
                          std::int32_t face, const glm::dvec3& block_normal, vessel::FaceRegion region) {
  ClosestPoint out;
  out.point_mm = q.point;
  out.distance_mm = std::sqrt(dsq);
  const double n_len = glm::length(block_normal);
  out.normal = q.feature.kind == FeatureKind::kFace && n_len > 0.5 ? block_normal / n_len
                                                                   : pseudo_normal(d, face, q.feature);
  out.signed_distance_mm = glm::dot(p - q.point, out.normal) < 0.0 ? -out.distance_mm : out.distance_mm;
  out.face = face;
  out.region = region;
  out.feature = q.feature.kind;
  out.feature_index = q.feature.index;
  return out;
}

glm::dvec3 block_normal(const detail::TriangleBlock& b, int lane) {
  return glm::dvec3{b.row[detail::kRowN][lane], b.row[detail::kRowN + 1][lane], b.row[detail::kRowN + 2][lane]};
}

}  // namespace

}  // namespace cathbox::collision

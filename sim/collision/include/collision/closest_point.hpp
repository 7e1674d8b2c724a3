#pragma once
// The answer of a closest-point query: the nearest point of the wall to a query point.
#include <cstdint>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::collision {

// Which part of the closest triangle the closest point lies on.
enum class FeatureKind : std::uint8_t {
  kFace = 0,    // the interior of the triangle
  kEdge = 1,    // edge `index`: from corner index to corner (index + 1) % 3
  kVertex = 2,  // corner `index`
};

struct ClosestPoint {
  glm::dvec3 point_mm{0.0};        // the nearest point on the wall
  double distance_mm = 0.0;        // unsigned distance from the query point
  double signed_distance_mm = 0.0; // negative inside the lumen (the closed mesh), positive outside
  glm::dvec3 normal{0.0};          // unit outward angle-weighted pseudo-normal of the closest feature
  std::int32_t face = -1;          // triangle index in the SurfaceMesh
  vessel::FaceRegion region{};     // the segment, junction or cap that triangle belongs to
  FeatureKind feature = FeatureKind::kFace;
  std::uint8_t feature_index = 0;
};

}  // namespace cathbox::collision

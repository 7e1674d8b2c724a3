#pragma once
// First intersection of a ray with the wall.
#include <cstdint>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::collision {

struct RayHit {
  double t = 0.0;              // ray parameter: point = origin + t * direction
  glm::dvec3 point_mm{0.0};
  glm::dvec3 normal{0.0};      // unit outward normal of the hit triangle
  bool front_face = false;     // true when the ray enters through the outside of the triangle
  std::int32_t face = -1;
  vessel::FaceRegion region{};
};

}  // namespace cathbox::collision

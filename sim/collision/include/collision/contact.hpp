#pragma once
// One contact between a tool primitive (sphere or capsule) and the wall.
#include <cstdint>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::collision {

struct Contact {
  glm::dvec3 wall_point_mm{0.0};  // the touching point on the wall
  glm::dvec3 normal{0.0};         // unit; points from the wall into the lumen (the direction that
                                  // pushes the tool primitive out of the wall)
  double depth_mm = 0.0;          // penetration depth (> 0 when touching)
  double segment_t = 0.0;         // capsule only: parameter in [0, 1] of the touching axis point
  std::int32_t face = -1;         // triangle index in the SurfaceMesh
  vessel::FaceRegion region{};
};

}  // namespace cathbox::collision

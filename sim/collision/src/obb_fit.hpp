#pragma once
// Oriented boxes in double and the principal axes of a point cloud.
#include <glm/vec3.hpp>

namespace cathbox::collision::detail {

struct Obb {
  glm::dvec3 center{0.0};
  glm::dvec3 axis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // orthonormal, right-handed
  glm::dvec3 half{0.0};
};

// Orthonormal eigenvectors of the symmetric 3x3 matrix {xx, yy, zz, xy, xz, yz}, largest
// eigenvalue first; the identity when the spread is isotropic or degenerate.
void principal_axes(const double cov[6], glm::dvec3 axes[3]);

}  // namespace cathbox::collision::detail

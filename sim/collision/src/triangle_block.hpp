#pragma once
// Writing one triangle into a lane of a 4-wide TriangleBlock (the tree's leaves): its float
// corners, unit normal and the dual basis (u, v) whose dot products with p - a give the
// barycentric coordinates of p's projection. Slivers get u = v = n = 0, which makes their float
// lower bound 0, so the exact stage always measures them.
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "tree_data.hpp"

namespace cathbox::collision::detail {

// a, b, c: the mesh's (float) corners in double; n: the unit face normal.
inline void set_triangle_lane(TriangleBlock& block, int lane, const glm::dvec3& a, const glm::dvec3& b,
                              const glm::dvec3& c, const glm::dvec3& n, std::int32_t face) {
  const glm::dvec3 e0 = b - a;
  const glm::dvec3 e1 = c - a;
  const double g00 = glm::dot(e0, e0);
  const double g01 = glm::dot(e0, e1);
  const double g11 = glm::dot(e1, e1);
  const double det = g00 * g11 - g01 * g01;
  const bool sliver = !(det > 1e-6 * g00 * g11);
  const glm::dvec3 u = sliver ? glm::dvec3{0.0} : (g11 * e0 - g01 * e1) / det;
  const glm::dvec3 v = sliver ? glm::dvec3{0.0} : (g00 * e1 - g01 * e0) / det;
  const glm::dvec3 normal = sliver ? glm::dvec3{0.0} : n;
  for (int k = 0; k < 3; ++k) {
    block.row[kRowA + k][lane] = static_cast<float>(a[k]);
    block.row[kRowB + k][lane] = static_cast<float>(a[k] + e0[k]);
    block.row[kRowC + k][lane] = static_cast<float>(a[k] + e1[k]);
    block.row[kRowN + k][lane] = static_cast<float>(normal[k]);
    block.row[kRowU + k][lane] = static_cast<float>(u[k]);
    block.row[kRowV + k][lane] = static_cast<float>(v[k]);
  }
  block.face[lane] = face;
}

// An empty lane: far away, so its bounds are huge; face -1.
inline void set_empty_triangle_lane(TriangleBlock& block, int lane) {
  for (int k = 0; k < 3; ++k)
    for (int r : {kRowA, kRowB, kRowC}) block.row[r + k][lane] = 1e30f;
  block.row[kRowN][lane] = 1.0f;
  block.face[lane] = -1;
}

}  // namespace cathbox::collision::detail

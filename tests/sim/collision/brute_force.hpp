#pragma once
// Reference answers by brute force over every triangle, written independently of the tree's
// own primitives (projection + edge clamping, plane crossing, ray parity).
#include <cstdint>
#include <optional>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::collision::testing {

// Triangles the tree leaves out: area below 1e-12 of the longest edge squared.
[[nodiscard]] bool is_degenerate(const vessel::SurfaceMesh& mesh, std::size_t face);

[[nodiscard]] double point_triangle_distance(const glm::dvec3& p, const glm::dvec3& a,
                                             const glm::dvec3& b, const glm::dvec3& c);
[[nodiscard]] double segment_triangle_distance(const glm::dvec3& p0, const glm::dvec3& p1,
                                               const glm::dvec3& a, const glm::dvec3& b,
                                               const glm::dvec3& c);

struct BruteNearest {
  double distance = 0.0;
  std::int32_t face = -1;
};
[[nodiscard]] BruteNearest nearest(const vessel::SurfaceMesh& mesh, const glm::dvec3& p);
[[nodiscard]] double segment_distance(const vessel::SurfaceMesh& mesh, const glm::dvec3& p0,
                                      const glm::dvec3& p1);
// Inside by the parity of crossings along three ray directions (majority).
[[nodiscard]] bool inside_by_parity(const vessel::SurfaceMesh& mesh, const glm::dvec3& p);
// Smallest t >= 0 where origin + t * dir meets a triangle.
[[nodiscard]] std::optional<double> first_hit(const vessel::SurfaceMesh& mesh, const glm::dvec3& origin,
                                              const glm::dvec3& dir);

[[nodiscard]] glm::dvec3 corner(const vessel::SurfaceMesh& mesh, std::size_t face, int k);

}  // namespace cathbox::collision::testing

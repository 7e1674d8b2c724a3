#pragma once
// A closed triangulated tube around a polyline (rings of m vertices, fan caps), outward
// oriented, for testing the mesh wall without the vessel module.
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::tool::testing {

inline vessel::SurfaceMesh tube_mesh(const std::vector<glm::dvec3>& axis, double radius, int m = 24,
                                     std::int32_t segment = 0) {
  vessel::SurfaceMesh mesh;
  const std::size_t rings = axis.size();
  glm::dvec3 prev_u(0.0);
  for (std::size_t i = 0; i < rings; ++i) {
    const glm::dvec3 t = glm::normalize(i + 1 < rings ? axis[i + 1] - axis[i] : axis[i] - axis[i - 1]);
    glm::dvec3 u = i == 0 ? glm::dvec3(1, 0, 0) : prev_u;
    if (std::abs(glm::dot(u, t)) > 0.9) u = glm::dvec3(0, 1, 0);
    u = glm::normalize(u - t * glm::dot(u, t));
    prev_u = u;
    const glm::dvec3 v = glm::cross(t, u);
    for (int j = 0; j < m; ++j) {
      const double a = 2.0 * M_PI * j / m;
      const glm::dvec3 dir = u * std::cos(a) + v * std::sin(a);
      mesh.positions_mm.push_back(glm::vec3(axis[i] + dir * radius));
      mesh.normals.push_back(glm::vec3(dir));
    }
  }
  auto idx = [&](std::size_t ring, int j) { return static_cast<std::uint32_t>(ring * m + ((j % m) + m) % m); };
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
    mesh.triangle_regions.push_back(vessel::FaceRegion{vessel::RegionKind::kSegment, segment});
  };
  for (std::size_t i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j < m; ++j) {
      tri(idx(i, j), idx(i, j + 1), idx(i + 1, j + 1));
      tri(idx(i, j), idx(i + 1, j + 1), idx(i + 1, j));
    }
  }
  // Caps: a centre vertex at each end.
  const auto c0 = static_cast<std::uint32_t>(mesh.positions_mm.size());
  mesh.positions_mm.push_back(glm::vec3(axis.front()));
  mesh.normals.push_back(glm::vec3(glm::normalize(axis.front() - axis[1])));
  const auto c1 = static_cast<std::uint32_t>(mesh.positions_mm.size());
  mesh.positions_mm.push_back(glm::vec3(axis.back()));
  mesh.normals.push_back(glm::vec3(glm::normalize(axis.back() - axis[rings - 2])));
  for (int j = 0; j < m; ++j) {
    tri(c0, idx(0, j + 1), idx(0, j));
    tri(c1, idx(rings - 1, j), idx(rings - 1, j + 1));
  }
  return mesh;
}

}  // namespace cathbox::tool::testing

#include "app/tube_mesh.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::app {
namespace {

glm::vec3 any_normal(const glm::vec3& t) {
  const glm::vec3 a = std::abs(t.x) < 0.9F ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  return glm::normalize(glm::cross(t, a));
}

glm::vec3 tangent_at(std::span<const glm::vec3> p, std::size_t i) {
  const std::size_t a = i == 0 ? 0 : i - 1;
  const std::size_t b = i + 1 < p.size() ? i + 1 : i;
  const glm::vec3 d = p[b] - p[a];
  const float len = glm::length(d);
  return len > 1e-9F ? d / len : glm::vec3(0.0F);
}

}  // namespace

std::size_t TubeMesh::vertex_count(std::size_t nodes, int sides) {
  return nodes * static_cast<std::size_t>(sides) + 1;
}

std::size_t TubeMesh::index_count(std::size_t nodes, int sides) {
  return nodes < 2 ? 0 : ((nodes - 1) * 6 + 3) * static_cast<std::size_t>(sides);
}

void TubeMesh::build(std::span<const glm::vec3> nodes_mm, std::span<const glm::vec3> frames,
                     float radius_mm, int sides) {
  positions_mm.clear();
  normals.clear();
  triangles.clear();
  if (nodes_mm.size() < 2 || sides < 3) return;
  const std::size_t n = nodes_mm.size();
  const auto s = static_cast<std::uint32_t>(sides);
  positions_mm.reserve(vertex_count(n, sides));
  normals.reserve(vertex_count(n, sides));
  triangles.reserve(index_count(n, sides));

  glm::vec3 prev_t = tangent_at(nodes_mm, 0);
  if (glm::length(prev_t) < 0.5F) prev_t = glm::vec3(1, 0, 0);
  glm::vec3 u = any_normal(prev_t);
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 t = tangent_at(nodes_mm, i);
    if (glm::length(t) < 0.5F) t = prev_t;
    if (i < frames.size() && glm::length(frames[i] - glm::dot(frames[i], t) * t) > 1e-4F) {
      u = glm::normalize(frames[i] - glm::dot(frames[i], t) * t);
    } else {
      // Parallel transport: remove the new tangent's component from the previous normal.
      const glm::vec3 w = u - glm::dot(u, t) * t;
      u = glm::length(w) > 1e-4F ? glm::normalize(w) : any_normal(t);
    }
    const glm::vec3 v = glm::cross(t, u);
    for (int k = 0; k < sides; ++k) {
      const float a = 6.2831853F * static_cast<float>(k) / static_cast<float>(sides);
      const glm::vec3 radial = std::cos(a) * u + std::sin(a) * v;
      positions_mm.push_back(nodes_mm[i] + radius_mm * radial);
      normals.push_back(radial);
    }
    prev_t = t;
  }
  // Distal cap apex, half a radius beyond the last node.
  positions_mm.push_back(nodes_mm[n - 1] + 0.5F * radius_mm * prev_t);
  normals.push_back(prev_t);

  for (std::uint32_t i = 0; i + 1 < n; ++i) {
    for (std::uint32_t k = 0; k < s; ++k) {
      const std::uint32_t a = i * s + k;
      const std::uint32_t b = i * s + (k + 1) % s;
      const std::uint32_t c = a + s;
      const std::uint32_t d = b + s;
      triangles.insert(triangles.end(), {a, b, d, a, d, c});
    }
  }
  const auto apex = static_cast<std::uint32_t>(positions_mm.size() - 1);
  const auto last = static_cast<std::uint32_t>((n - 1) * s);
  for (std::uint32_t k = 0; k < s; ++k) {
    triangles.insert(triangles.end(), {last + k, last + (k + 1) % s, apex});
  }
}

}  // namespace cathbox::app

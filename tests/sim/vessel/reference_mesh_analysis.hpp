#pragma once
// The mesh analysis as it was first written (hash maps of directed edges, a map per vertex fan):
// the reference the linear-time analyze_mesh must agree with field for field
// (mesh_analysis_test.cpp), and its peer in bench_vessel.
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "vessel/mesh_analysis.hpp"

namespace cathbox::vessel::test {

[[nodiscard]] inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; }

inline MeshAnalysis reference_analysis(const SurfaceMesh& mesh) {
  MeshAnalysis out;
  out.vertices = mesh.vertex_count();
  out.triangles = mesh.triangle_count();
  std::unordered_map<std::uint64_t, std::uint32_t> directed;  // directed edge -> uses
  directed.reserve(mesh.triangles.size() * 2);
  const auto& t = mesh.triangles;
  for (std::size_t f = 0; f + 2 < t.size(); f += 3) {
    const glm::dvec3 a(mesh.positions_mm[t[f]]);
    const glm::dvec3 b(mesh.positions_mm[t[f + 1]]);
    const glm::dvec3 c(mesh.positions_mm[t[f + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    out.area_mm2 += 0.5 * glm::length(n);
    out.signed_volume_mm3 += glm::dot(a, glm::cross(b, c)) / 6.0;
    if (t[f] == t[f + 1] || t[f + 1] == t[f + 2] || t[f] == t[f + 2] || glm::length(n) == 0.0) {
      ++out.degenerate_triangles;
    }
    for (int e = 0; e < 3; ++e) ++directed[edge_key(t[f + e], t[f + (e + 1) % 3])];
  }
  for (const auto& [k, uses] : directed) {
    const auto a = static_cast<std::uint32_t>(k >> 32);
    const auto b = static_cast<std::uint32_t>(k & 0xffffffffu);
    const auto rev = directed.find(edge_key(b, a));
    const std::uint32_t back = rev == directed.end() ? 0 : rev->second;
    if (uses > 1) ++out.misoriented_edges;
    if (a > b && back > 0) continue;  // count each undirected edge once (from a < b or lone)
    ++out.edges;
    const std::uint32_t total = uses + back;
    if (total == 1) ++out.boundary_edges;
    else if (total > 2) ++out.nonmanifold_edges;
  }
  // Vertex fans: the link of each vertex (edges opposite to it) must be one path or cycle.
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> link(mesh.vertex_count());
  for (std::size_t f = 0; f + 2 < t.size(); f += 3) {
    for (int k = 0; k < 3; ++k) {
      link[t[f + k]].emplace_back(t[f + (k + 1) % 3], t[f + (k + 2) % 3]);
    }
  }
  std::unordered_map<std::uint32_t, std::uint32_t> next;
  for (std::size_t v = 0; v < link.size(); ++v) {
    const auto& edges = link[v];
    if (edges.empty()) continue;
    next.clear();
    bool bad = false;
    for (const auto& [a, b] : edges) {
      if (!next.emplace(a, b).second) bad = true;
    }
    if (!bad) {
      // Walk from a start that has no predecessor (open fan) or anywhere (closed fan).
      std::unordered_map<std::uint32_t, int> has_pred;
      for (const auto& [a, b] : edges) has_pred[b] = 1;
      std::uint32_t start = edges.front().first;
      for (const auto& [a, b] : edges) {
        if (!has_pred.count(a)) start = a;
      }
      std::size_t steps = 0;
      std::uint32_t cur = start;
      while (steps <= edges.size()) {
        const auto it = next.find(cur);
        if (it == next.end()) break;
        cur = it->second;
        ++steps;
        if (cur == start) break;
      }
      bad = steps != edges.size();
    }
    if (bad) ++out.nonmanifold_vertices;
  }
  out.euler_characteristic =
      static_cast<int>(out.vertices) - static_cast<int>(out.edges) + static_cast<int>(out.triangles);
  return out;
}



}  // namespace cathbox::vessel::test

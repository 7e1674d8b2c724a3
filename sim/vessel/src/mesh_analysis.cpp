#include "vessel/mesh_analysis.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace cathbox::vessel {
namespace {

[[nodiscard]] std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; }

// Segment p->q against triangle (a, b, c), excluding touching at the ends (Moeller-Trumbore).
[[nodiscard]] bool segment_hits_triangle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a,
                                         const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 dir = q - p;
  const glm::dvec3 e1 = b - a;
  const glm::dvec3 e2 = c - a;
  const glm::dvec3 h = glm::cross(dir, e2);
  const double det = glm::dot(e1, h);
  const double scale = glm::length(e1) * glm::length(e2) * glm::length(dir);
  if (std::abs(det) <= 1e-12 * scale) return false;  // parallel or coplanar
  const double inv = 1.0 / det;
  const glm::dvec3 s = p - a;
  const double u = glm::dot(s, h) * inv;
  if (u <= 0.0 || u >= 1.0) return false;
  const glm::dvec3 qv = glm::cross(s, e1);
  const double v = glm::dot(dir, qv) * inv;
  if (v <= 0.0 || u + v >= 1.0) return false;
  const double t = glm::dot(e2, qv) * inv;
  return t > 0.0 && t < 1.0;
}

}  // namespace

MeshAnalysis analyze_mesh(const SurfaceMesh& mesh) {
  MeshAnalysis out;
  out.vertices = mesh.vertex_count();
  out.triangles = mesh.triangle_count();
  const auto& t = mesh.triangles;
  const std::size_t nv = mesh.vertex_count();
  // Geometry, and each triangle's half-edges a -> b (with the third corner c) grouped by their
  // source a (counting sort): a vertex's outgoing half-edges are its link edges b -> c.
  std::vector<std::uint32_t> first(nv + 1, 0);
  for (std::size_t f = 0; f + 2 < t.size(); f += 3) {
    const bool in_range = t[f] < nv && t[f + 1] < nv && t[f + 2] < nv;
    if (!in_range) {
      ++out.degenerate_triangles;
      continue;
    }
    const glm::dvec3 a(mesh.positions_mm[t[f]]);
    const glm::dvec3 b(mesh.positions_mm[t[f + 1]]);
    const glm::dvec3 c(mesh.positions_mm[t[f + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double twice_area = glm::length(n);
    out.area_mm2 += 0.5 * twice_area;
    out.signed_volume_mm3 += glm::dot(a, glm::cross(b, c)) / 6.0;
    if (t[f] == t[f + 1] || t[f + 1] == t[f + 2] || t[f] == t[f + 2] || twice_area == 0.0) ++out.degenerate_triangles;
    for (std::size_t k = 0; k < 3; ++k) ++first[t[f + k] + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  struct HalfEdge {
    std::uint32_t target;  // b
    std::uint32_t third;   // c
  };
  std::vector<HalfEdge> out_edges(first[nv]);
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t f = 0; f + 2 < t.size(); f += 3) {
      if (t[f] >= nv || t[f + 1] >= nv || t[f + 2] >= nv) continue;
      for (std::size_t k = 0; k < 3; ++k) {
        out_edges[fill[t[f + k]]++] = {t[f + (k + 1) % 3], t[f + (k + 2) % 3]};
      }
    }
  }
  for (std::uint32_t a = 0; a < nv; ++a) {
    const std::uint32_t begin = first[a];
    const std::uint32_t end = first[a + 1];
    if (begin == end) continue;
    // The common case first: a's link is one closed cycle through all its corners (an interior
    // vertex of a closed, consistently oriented manifold). Then every a -> b is used once and
    // b -> a once, so each edge is a proper interior edge, counted from its smaller end.
    if (end - begin <= 32) {
      std::uint32_t visited = 0;
      std::uint32_t cur = out_edges[begin].target;
      std::uint32_t steps = 0;
      for (; steps < end - begin; ++steps) {
        std::uint32_t j = begin;
        while (j < end && out_edges[j].target != cur) ++j;
        if (j == end || (visited >> (j - begin) & 1u) || cur == a) break;
        visited |= 1u << (j - begin);
        cur = out_edges[j].third;
      }
      if (steps == end - begin && cur == out_edges[begin].target) {
        for (std::uint32_t i = begin; i < end; ++i) out.edges += out_edges[i].target > a ? 1u : 0u;
        continue;
      }
    }
    bool bad = false;  // the link of a (its edges b -> c) is not one path or cycle
    for (std::uint32_t i = begin; i < end; ++i) {
      const std::uint32_t b = out_edges[i].target;
      bool seen = false;
      for (std::uint32_t j = begin; j < i && !seen; ++j) seen = out_edges[j].target == b;
      if (seen) {  // a second a -> b: counted with the first
        bad = true;
        continue;
      }
      // Half-edges a -> b, and b -> a: in a triangle (a, b, c) the half-edge into a is c -> a, so
      // a's own corners hold every half-edge into it as their third vertex.
      std::uint32_t forward = 0;
      std::uint32_t back = 0;
      for (std::uint32_t j = begin; j < end; ++j) {
        forward += out_edges[j].target == b ? 1u : 0u;
        back += out_edges[j].third == b ? 1u : 0u;
      }
      // Each directed edge once; each undirected edge once (from a < b, or alone).
      if (forward > 1) ++out.misoriented_edges;
      if (a > b && back > 0) continue;
      ++out.edges;
      const std::uint32_t total = forward + back;
      if (total == 1) ++out.boundary_edges;
      else if (total > 2) ++out.nonmanifold_edges;
    }
    if (!bad) {
      // Walk the link from a start without predecessor (an open fan) or from its first edge.
      std::uint32_t start = out_edges[begin].target;
      for (std::uint32_t i = begin; i < end; ++i) {
        bool has_predecessor = false;
        for (std::uint32_t j = begin; j < end && !has_predecessor; ++j) has_predecessor = out_edges[j].third == out_edges[i].target;
        if (!has_predecessor) start = out_edges[i].target;
      }
      std::size_t steps = 0;
      std::uint32_t cur = start;
      const std::size_t n = end - begin;
      while (steps <= n) {
        std::uint32_t next = begin;
        while (next < end && out_edges[next].target != cur) ++next;
        if (next == end) break;
        cur = out_edges[next].third;
        ++steps;
        if (cur == start) break;
      }
      bad = steps != n;
    }
    if (bad) ++out.nonmanifold_vertices;
  }
  out.euler_characteristic =
      static_cast<int>(out.vertices) - static_cast<int>(out.edges) + static_cast<int>(out.triangles);
  return out;
}

std::size_t count_self_intersections(const SurfaceMesh& mesh, std::size_t limit) {
  const auto& t = mesh.triangles;
  const std::size_t n = mesh.triangle_count();
  if (n == 0) return 0;
  double mean_edge = 0.0;
  for (std::size_t f = 0; f < n; ++f) {
    mean_edge += glm::length(mesh.positions_mm[t[3 * f]] - mesh.positions_mm[t[3 * f + 1]]);
  }
  const double cell = std::max(1e-6, 2.0 * mean_edge / static_cast<double>(n));
  const auto cell_of = [cell](double x) { return static_cast<std::int64_t>(std::floor(x / cell)); };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  const auto cell_key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) | (static_cast<std::uint64_t>(y & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(z & 0x1fffff);
  };
  std::vector<std::array<glm::dvec3, 3>> tri(n);
  for (std::size_t f = 0; f < n; ++f) {
    for (int k = 0; k < 3; ++k) tri[f][static_cast<std::size_t>(k)] = glm::dvec3(mesh.positions_mm[t[3 * f + k]]);
    glm::dvec3 lo = glm::min(glm::min(tri[f][0], tri[f][1]), tri[f][2]);
    glm::dvec3 hi = glm::max(glm::max(tri[f][0], tri[f][1]), tri[f][2]);
    for (std::int64_t x = cell_of(lo.x); x <= cell_of(hi.x); ++x) {
      for (std::int64_t y = cell_of(lo.y); y <= cell_of(hi.y); ++y) {
        for (std::int64_t z = cell_of(lo.z); z <= cell_of(hi.z); ++z) {
          grid[cell_key(x, y, z)].push_back(static_cast<std::uint32_t>(f));
        }
      }
    }
  }
  std::size_t found = 0;
  std::unordered_map<std::uint64_t, char> tested;
  for (const auto& [k, list] : grid) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      for (std::size_t j = i + 1; j < list.size(); ++j) {
        const std::uint32_t a = std::min(list[i], list[j]);
        const std::uint32_t b = std::max(list[i], list[j]);
        bool shared = false;
        for (int p = 0; p < 3; ++p) {
          for (int q = 0; q < 3; ++q) shared |= t[3 * a + p] == t[3 * b + q];
        }
        if (shared || !tested.emplace(key(a, b), 1).second) continue;
        bool hit = false;
        for (int e = 0; e < 3 && !hit; ++e) {
          hit = segment_hits_triangle(tri[a][e], tri[a][(e + 1) % 3], tri[b][0], tri[b][1], tri[b][2]) ||
                segment_hits_triangle(tri[b][e], tri[b][(e + 1) % 3], tri[a][0], tri[a][1], tri[a][2]);
        }
        if (hit && ++found >= limit) return found;
      }
    }
  }
  return found;
}

}  // namespace cathbox::vessel

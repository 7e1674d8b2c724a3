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

struct HalfEdge {
  std::uint32_t target;  // b
  std::uint32_t third;   // c
};

// Each triangle's half-edges a -> b (with the third corner c) grouped by their source a
// (counting sort): a vertex's outgoing half-edges are its link edges b -> c. Also adds the
// geometry (area, signed volume) and the degenerate triangles to `out`.
struct VertexLinks {
  std::vector<std::uint32_t> first;  // vertex a's half-edges are [first[a], first[a + 1])
  std::vector<HalfEdge> edges;
};

VertexLinks measure_and_link(const SurfaceMesh& mesh, MeshAnalysis& out) {
  const auto& t = mesh.triangles;
  const std::size_t nv = mesh.vertex_count();
  VertexLinks links;
  links.first.assign(nv + 1, 0);
  std::vector<std::uint32_t>& first = links.first;
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
  links.edges.resize(first[nv]);
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  for (std::size_t f = 0; f + 2 < t.size(); f += 3) {
    if (t[f] >= nv || t[f + 1] >= nv || t[f + 2] >= nv) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      links.edges[fill[t[f + k]]++] = {t[f + (k + 1) % 3], t[f + (k + 2) % 3]};
    }
  }
  return links;
}

// The common case: a's link is one closed cycle through all its corners (an interior vertex of
// a closed, consistently oriented manifold). Checked for up to 32 corners.
bool link_is_closed_cycle(const std::vector<HalfEdge>& out_edges, std::uint32_t a, std::uint32_t begin, std::uint32_t end) {
  if (end - begin > 32) return false;
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
  return steps == end - begin && cur == out_edges[begin].target;
}

// Counts the edges from a (each undirected edge once: from a < b, or alone) as boundary,
// non-manifold or misoriented; returns whether some a -> b appears twice.
bool count_vertex_edges(const std::vector<HalfEdge>& out_edges, std::uint32_t a, std::uint32_t begin, std::uint32_t end,
                        MeshAnalysis& out) {
  bool repeated = false;
  for (std::uint32_t i = begin; i < end; ++i) {
    const std::uint32_t b = out_edges[i].target;
    bool seen = false;
    for (std::uint32_t j = begin; j < i && !seen; ++j) seen = out_edges[j].target == b;
    if (seen) {  // a second a -> b: counted with the first
      repeated = true;
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
    if (forward > 1) ++out.misoriented_edges;
    if (a > b && back > 0) continue;
    ++out.edges;
    const std::uint32_t total = forward + back;
    if (total == 1) ++out.boundary_edges;
    else if (total > 2) ++out.nonmanifold_edges;
  }
  return repeated;
}

// Whether a's link (its edges b -> c) is one path or cycle: walked from a start without
// predecessor (an open fan) or from its first edge, it covers every edge.
bool link_is_one_path(const std::vector<HalfEdge>& out_edges, std::uint32_t begin, std::uint32_t end) {
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
  return steps == n;
}

using Triangle = std::array<glm::dvec3, 3>;
using CellGrid = std::unordered_map<std::uint64_t, std::vector<std::uint32_t>>;

// Each triangle in every grid cell its bounding box touches (cells twice the mean edge).
CellGrid bin_triangles(const std::vector<Triangle>& tri, double cell) {
  const auto cell_of = [cell](double x) { return static_cast<std::int64_t>(std::floor(x / cell)); };
  const auto cell_key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) | (static_cast<std::uint64_t>(y & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(z & 0x1fffff);
  };
  CellGrid grid;
  for (std::size_t f = 0; f < tri.size(); ++f) {
    const glm::dvec3 lo = glm::min(glm::min(tri[f][0], tri[f][1]), tri[f][2]);
    const glm::dvec3 hi = glm::max(glm::max(tri[f][0], tri[f][1]), tri[f][2]);
    for (std::int64_t x = cell_of(lo.x); x <= cell_of(hi.x); ++x) {
      for (std::int64_t y = cell_of(lo.y); y <= cell_of(hi.y); ++y) {
        for (std::int64_t z = cell_of(lo.z); z <= cell_of(hi.z); ++z) {
          grid[cell_key(x, y, z)].push_back(static_cast<std::uint32_t>(f));
        }
      }
    }
  }
  return grid;
}

[[nodiscard]] bool share_vertex(const std::vector<std::uint32_t>& t, std::uint32_t a, std::uint32_t b) {
  bool shared = false;
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) shared |= t[3 * a + p] == t[3 * b + q];
  }
  return shared;
}

[[nodiscard]] bool triangles_cross(const Triangle& a, const Triangle& b) {
  bool hit = false;
  for (int e = 0; e < 3 && !hit; ++e) {
    hit = segment_hits_triangle(a[e], a[(e + 1) % 3], b[0], b[1], b[2]) ||
          segment_hits_triangle(b[e], b[(e + 1) % 3], a[0], a[1], a[2]);
  }
  return hit;
}

}  // namespace

MeshAnalysis analyze_mesh(const SurfaceMesh& mesh) {
  MeshAnalysis out;
  out.vertices = mesh.vertex_count();
  out.triangles = mesh.triangle_count();
  const std::size_t nv = mesh.vertex_count();
  const VertexLinks links = measure_and_link(mesh, out);
  for (std::uint32_t a = 0; a < nv; ++a) {
    const std::uint32_t begin = links.first[a];
    const std::uint32_t end = links.first[a + 1];
    if (begin == end) continue;
    // A closed cycle: every a -> b is used once and b -> a once, so each edge is a proper
    // interior edge, counted from its smaller end.
    if (link_is_closed_cycle(links.edges, a, begin, end)) {
      for (std::uint32_t i = begin; i < end; ++i) out.edges += links.edges[i].target > a ? 1u : 0u;
      continue;
    }
    const bool repeated = count_vertex_edges(links.edges, a, begin, end, out);
    if (repeated || !link_is_one_path(links.edges, begin, end)) ++out.nonmanifold_vertices;
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
  std::vector<Triangle> tri(n);
  for (std::size_t f = 0; f < n; ++f) {
    for (int k = 0; k < 3; ++k) tri[f][static_cast<std::size_t>(k)] = glm::dvec3(mesh.positions_mm[t[3 * f + k]]);
  }
  const CellGrid grid = bin_triangles(tri, cell);
  std::size_t found = 0;
  std::unordered_map<std::uint64_t, char> tested;
  for (const auto& [k, list] : grid) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      for (std::size_t j = i + 1; j < list.size(); ++j) {
        const std::uint32_t a = std::min(list[i], list[j]);
        const std::uint32_t b = std::max(list[i], list[j]);
        if (share_vertex(t, a, b) || !tested.emplace(key(a, b), 1).second) continue;
        if (triangles_cross(tri[a], tri[b]) && ++found >= limit) return found;
      }
    }
  }
  return found;
}

}  // namespace cathbox::vessel

#include "convex_hull.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>

namespace cathbox::vessel::detail {
namespace {

[[nodiscard]] double orient(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  return glm::dot(glm::cross(b - a, c - a), d - a);
}

[[nodiscard]] std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// The points moved to the unit box of their extent with a deterministic perturbation
// (xorshift), 1e-7 of the extent; empty for a degenerate or non-finite extent.
std::vector<glm::dvec3> normalised_jittered(const std::vector<glm::dvec3>& input) {
  glm::dvec3 lo = input[0];
  glm::dvec3 hi = input[0];
  for (const glm::dvec3& p : input) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double scale = glm::length(hi - lo);
  if (!(scale > 0.0) || !std::isfinite(scale)) return {};
  std::vector<glm::dvec3> pts(input.size());
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto next = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0) - 0.5;
  };
  for (std::size_t i = 0; i < input.size(); ++i) {
    const glm::dvec3 jitter(next(), next(), next());
    pts[i] = (input[i] - lo) / scale + 1e-7 * jitter;
  }
  return pts;
}

// Initial tetrahedron from well spread points, its first face pointing outward; empty when the
// points are (nearly) coplanar.
std::vector<std::array<int, 3>> initial_tetrahedron(const std::vector<glm::dvec3>& pts) {
  const int n = static_cast<int>(pts.size());
  int i0 = 0;
  int i1 = 0;
  for (int i = 1; i < n; ++i) {
    if (glm::length(pts[i] - pts[i0]) > glm::length(pts[i1] - pts[i0])) i1 = i;
  }
  int i2 = -1;
  double best = 0.0;
  for (int i = 0; i < n; ++i) {
    const double area = glm::length(glm::cross(pts[i1] - pts[i0], pts[i] - pts[i0]));
    if (area > best) {
      best = area;
      i2 = i;
    }
  }
  if (i2 < 0) return {};
  int i3 = -1;
  best = 0.0;
  for (int i = 0; i < n; ++i) {
    const double vol = std::abs(orient(pts[i0], pts[i1], pts[i2], pts[i]));
    if (vol > best) {
      best = vol;
      i3 = i;
    }
  }
  if (i3 < 0 || best < 1e-18) return {};
  if (orient(pts[i0], pts[i1], pts[i2], pts[i3]) > 0.0) std::swap(i1, i2);
  // Now i3 is below face (i0,i1,i2), so that face points outward.
  return {{i0, i1, i2}, {i0, i3, i1}, {i1, i3, i2}, {i2, i3, i0}};
}

// An incremental hull: faces with their alive flags and the scratch of one insertion.
struct IncrementalHull {
  std::vector<std::array<int, 3>> faces;
  std::vector<char> alive;
  std::vector<std::size_t> visible;
  std::vector<std::uint64_t> visible_edges;  // sorted; a few dozen at most

  // Adds point p: removes the faces it sees and fans their horizon to it.
  void add(const std::vector<glm::dvec3>& pts, int p) {
    visible.clear();
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!alive[f]) continue;
      const auto& t = faces[f];
      if (orient(pts[t[0]], pts[t[1]], pts[t[2]], pts[p]) > 0.0) visible.push_back(f);
    }
    if (visible.empty()) return;  // inside
    visible_edges.clear();
    for (std::size_t f : visible) {
      const auto& t = faces[f];
      for (int e = 0; e < 3; ++e) visible_edges.push_back(edge_key(t[e], t[(e + 1) % 3]));
    }
    std::sort(visible_edges.begin(), visible_edges.end());
    for (std::size_t f : visible) {
      const auto t = faces[f];
      alive[f] = 0;
      for (int e = 0; e < 3; ++e) {
        const int a = t[e];
        const int b = t[(e + 1) % 3];
        if (!std::binary_search(visible_edges.begin(), visible_edges.end(), edge_key(b, a))) {
          faces.push_back({a, b, p});
          alive.push_back(1);
        }
      }
    }
  }
};

}  // namespace

std::vector<std::array<int, 3>> convex_hull(const std::vector<glm::dvec3>& input) {
  const int n = static_cast<int>(input.size());
  if (n < 4) return {};
  const std::vector<glm::dvec3> pts = normalised_jittered(input);
  if (pts.empty()) return {};
  IncrementalHull hull;
  hull.faces = initial_tetrahedron(pts);
  if (hull.faces.empty()) return {};
  hull.alive.assign(hull.faces.size(), 1);
  hull.faces.reserve(8 * static_cast<std::size_t>(n));
  hull.alive.reserve(hull.faces.capacity());
  const std::array<int, 3> first = hull.faces[0];
  const int apex = hull.faces[1][1];
  for (int p = 0; p < n; ++p) {
    if (p == first[0] || p == first[1] || p == first[2] || p == apex) continue;
    hull.add(pts, p);
  }
  std::vector<std::array<int, 3>> out;
  for (std::size_t f = 0; f < hull.faces.size(); ++f) {
    if (hull.alive[f]) out.push_back(hull.faces[f]);
  }
  return out;
}

}  // namespace cathbox::vessel::detail

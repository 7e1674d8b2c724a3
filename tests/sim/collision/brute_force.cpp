#include "brute_force.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::collision::testing {

glm::dvec3 corner(const vessel::SurfaceMesh& m, std::size_t face, int k) {
  return glm::dvec3(m.positions_mm[m.triangles[3 * face + static_cast<std::size_t>(k)]]);
}

bool is_degenerate(const vessel::SurfaceMesh& m, std::size_t face) {
  const glm::dvec3 a = corner(m, face, 0), b = corner(m, face, 1), c = corner(m, face, 2);
  const double longest = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
  return !(glm::length(glm::cross(b - a, c - a)) > 1e-12 * longest);
}

namespace {

double point_segment_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len = glm::dot(ab, ab);
  const double t = len > 0.0 ? std::clamp(glm::dot(p - a, ab) / len, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

// Distance between segments by golden-section search on the convex function s -> d(P(s), Q).
double segment_segment_distance(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& q0,
                                const glm::dvec3& q1) {
  auto f = [&](double s) { return point_segment_distance(p0 + s * (p1 - p0), q0, q1); };
  double lo = 0.0, hi = 1.0;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 120; ++i) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    }
  }
  return std::min({f1, f2, f(0.0), f(1.0)});
}

bool inside_triangle_plane(const glm::dvec3& x, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                           const glm::dvec3& n) {
  return glm::dot(glm::cross(b - a, x - a), n) >= 0.0 && glm::dot(glm::cross(c - b, x - b), n) >= 0.0 &&
         glm::dot(glm::cross(a - c, x - c), n) >= 0.0;
}

}  // namespace

double point_triangle_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                               const glm::dvec3& c) {
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  const double h = glm::dot(p - a, n);
  const glm::dvec3 x = p - h * n;
  if (inside_triangle_plane(x, a, b, c, n)) return std::abs(h);
  return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                   point_segment_distance(p, c, a)});
}

double segment_triangle_distance(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& a,
                                 const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  const double h0 = glm::dot(p0 - a, n);
  const double h1 = glm::dot(p1 - a, n);
  if ((h0 <= 0.0 && h1 >= 0.0) || (h0 >= 0.0 && h1 <= 0.0)) {
    if (h0 != h1) {
      const glm::dvec3 x = p0 + (h0 / (h0 - h1)) * (p1 - p0);
      if (inside_triangle_plane(x, a, b, c, n)) return 0.0;
    }
  }
  return std::min({point_triangle_distance(p0, a, b, c), point_triangle_distance(p1, a, b, c),
                   segment_segment_distance(p0, p1, a, b), segment_segment_distance(p0, p1, b, c),
                   segment_segment_distance(p0, p1, c, a)});
}

BruteNearest nearest(const vessel::SurfaceMesh& m, const glm::dvec3& p) {
  BruteNearest best{std::numeric_limits<double>::infinity(), -1};
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    if (is_degenerate(m, t)) continue;
    const double d = point_triangle_distance(p, corner(m, t, 0), corner(m, t, 1), corner(m, t, 2));
    if (d < best.distance) best = {d, static_cast<std::int32_t>(t)};
  }
  return best;
}

double segment_distance(const vessel::SurfaceMesh& m, const glm::dvec3& p0, const glm::dvec3& p1) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    if (is_degenerate(m, t)) continue;
    best = std::min(best, segment_triangle_distance(p0, p1, corner(m, t, 0), corner(m, t, 1), corner(m, t, 2)));
  }
  return best;
}

namespace {

std::optional<double> hit(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
                          const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double denom = glm::dot(d, n);
  if (denom == 0.0) return std::nullopt;
  const double t = glm::dot(a - o, n) / denom;
  if (t < 0.0) return std::nullopt;
  if (!inside_triangle_plane(o + t * d, a, b, c, n)) return std::nullopt;
  return t;
}

}  // namespace

bool inside_by_parity(const vessel::SurfaceMesh& m, const glm::dvec3& p) {
  const glm::dvec3 dirs[3] = {{0.5377, 0.1834, -0.8229}, {-0.4336, 0.8442, 0.3150}, {0.2177, -0.6517, 0.7267}};
  int votes = 0;
  for (const auto& d : dirs) {
    int crossings = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
      if (!is_degenerate(m, t) && hit(p, d, corner(m, t, 0), corner(m, t, 1), corner(m, t, 2))) ++crossings;
    votes += crossings % 2;
  }
  return votes >= 2;
}

std::optional<double> first_hit(const vessel::SurfaceMesh& m, const glm::dvec3& origin, const glm::dvec3& dir) {
  std::optional<double> best;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    if (is_degenerate(m, t)) continue;
    const auto h = hit(origin, dir, corner(m, t, 0), corner(m, t, 1), corner(m, t, 2));
    if (h && (!best || *h < *best)) best = h;
  }
  return best;
}

}  // namespace cathbox::collision::testing

#include "junction_patch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "convex_hull.hpp"
#include "junction_pairing.hpp"

namespace cathbox::vessel::detail {
namespace {

using Triangle = std::array<int, 3>;

// The patch from the hull of `hull_points` (the rings, or their images on the sphere), paired into
// quads by the lengths of the real `points`' edges.
JunctionPatchResult hull_patch(const std::vector<glm::dvec3>& hull_points, const std::vector<glm::dvec3>& points,
                               const std::vector<JunctionRing>& rings, int ring_points) {
  JunctionPatchResult result;
  const int m_count = ring_points;
  const auto ring_of = [m_count](int v) { return v / m_count; };
  const std::vector<Triangle> hull = convex_hull(hull_points);
  if (hull.empty()) {
    result.error = "its rings span no volume";
    return result;
  }
  std::vector<Triangle> patch;
  for (const Triangle& t : hull) {
    if (ring_of(t[0]) == ring_of(t[1]) && ring_of(t[1]) == ring_of(t[2])) continue;  // a ring's own disc
    patch.push_back(t);
  }
  // The patch must be bounded by exactly the ring edges, each once, in the direction opposite
  // to the tube's use; every other edge must be shared by two patch triangles.
  std::unordered_map<std::uint64_t, int> edges;
  for (const Triangle& t : patch) {
    for (int e = 0; e < 3; ++e) ++edges[directed_edge_key(t[e], t[(e + 1) % 3])];
  }
  std::size_t ring_edges = 0;
  for (const auto& [key, count] : edges) {
    const int a = static_cast<int>(key >> 32);
    const int b = static_cast<int>(key & 0xffffffffu);
    if (count != 1) {
      result.error = "its hull is not manifold";
      return result;
    }
    if (ring_of(a) == ring_of(b)) {
      const int r = ring_of(a);
      const int ma = a % m_count;
      const int mb = b % m_count;
      const bool forward = mb == (ma + 1) % m_count;
      const bool backward = ma == (mb + 1) % m_count;
      const bool tube_forward = rings[static_cast<std::size_t>(r)].tube_runs_forward;
      if (!(tube_forward ? backward : forward)) {
        result.error = "branches overlap (a ring is not on the junction's hull)";
        return result;
      }
      ++ring_edges;
    } else if (edges.count(directed_edge_key(b, a)) == 0) {
      result.error = "its hull is open";
      return result;
    }
  }
  if (ring_edges != rings.size() * static_cast<std::size_t>(m_count)) {
    result.error = "branches overlap (a ring is not on the junction's hull)";
    return result;
  }
  result.faces = pair_into_quads(patch, points, ring_points);
  return result;
}

constexpr double kMinDirectionAngle = 10.0 * std::numbers::pi / 180.0;  // directions closer than this are pushed apart
constexpr double kDirectionStep = 0.05;                    // radians per push
constexpr int kDirectionIterations = 400;
constexpr double kCapShare = 0.4;   // a ring's circle: this share of the angle to the nearest other direction
constexpr double kMaxCapAngle = 1.0;  // radians

// A unit vector perpendicular to u leaning towards `towards` (any perpendicular when it is along u).
glm::dvec3 perpendicular_towards(const glm::dvec3& u, const glm::dvec3& towards) {
  glm::dvec3 side = towards - glm::dot(towards, u) * u;
  if (glm::length(side) < 1e-9) {
    side = std::abs(u.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    side -= glm::dot(side, u) * u;
  }
  return glm::normalize(side);
}

// The rings' leaving directions, pairs closer than kMinDirectionAngle pushed apart along the
// great circle through them (their ring centres' offset decides the side when they coincide).
std::vector<glm::dvec3> separated_directions(const std::vector<JunctionRingFrame>& frames) {
  std::vector<glm::dvec3> u;
  for (const JunctionRingFrame& f : frames) u.push_back(glm::normalize(f.out));
  const double close = std::cos(kMinDirectionAngle);
  for (int iteration = 0; iteration < kDirectionIterations; ++iteration) {
    bool moved = false;
    for (std::size_t i = 0; i < u.size(); ++i) {
      for (std::size_t j = i + 1; j < u.size(); ++j) {
        if (glm::dot(u[i], u[j]) < close) continue;
        const glm::dvec3 apart = u[i] - u[j];
        const glm::dvec3 hint = glm::length(apart) > 1e-9 ? apart : frames[i].center - frames[j].center;
        const glm::dvec3 side_i = perpendicular_towards(u[i], hint);
        const glm::dvec3 side_j = perpendicular_towards(u[j], -hint);
        u[i] = glm::normalize(u[i] + kDirectionStep * side_i);
        u[j] = glm::normalize(u[j] + kDirectionStep * side_j);
        moved = true;
      }
    }
    if (!moved) break;
  }
  return u;
}

}  // namespace

JunctionPatchResult build_junction_patch(const std::vector<glm::dvec3>& points, const std::vector<JunctionRing>& rings,
                                         int ring_points) {
  return hull_patch(points, points, rings, ring_points);
}

JunctionPatchResult build_spherical_junction_patch(const std::vector<glm::dvec3>& points,
                                                   const std::vector<JunctionRing>& rings,
                                                   const std::vector<JunctionRingFrame>& frames, int ring_points) {
  const std::vector<glm::dvec3> u = separated_directions(frames);
  std::vector<glm::dvec3> sphere;
  sphere.reserve(points.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    double nearest = std::numbers::pi;
    for (std::size_t j = 0; j < u.size(); ++j) {
      if (j != i) nearest = std::min(nearest, std::acos(std::clamp(glm::dot(u[i], u[j]), -1.0, 1.0)));
    }
    const double cap = std::min(kCapShare * nearest, kMaxCapAngle);
    // The ring's own frame turned to be perpendicular to u, keeping its sense of rotation about
    // the leaving direction (the hull's face for the ring must run its edges as the tube does).
    const glm::dvec3 normal = perpendicular_towards(u[i], frames[i].normal);
    const double sense = glm::dot(glm::cross(frames[i].normal, frames[i].binormal), frames[i].out) < 0.0 ? -1.0 : 1.0;
    const glm::dvec3 binormal = sense * glm::cross(u[i], normal);
    for (int m = 0; m < ring_points; ++m) {
      const double angle = 2.0 * std::numbers::pi * m / ring_points;
      sphere.push_back(std::cos(cap) * u[i] + std::sin(cap) * (std::cos(angle) * normal + std::sin(angle) * binormal));
    }
  }
  return hull_patch(sphere, points, rings, ring_points);
}

}  // namespace cathbox::vessel::detail

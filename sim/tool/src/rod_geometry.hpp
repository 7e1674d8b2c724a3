#pragma once
// Private to the rod's sources: the geometry they share (parallel transport of frames, a unit
// normal to a tangent) and the look-up of a material station along the tool. Inline: the frames
// call them per edge and step.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "tool/rod.hpp"

namespace cathbox::tool::rod_detail {

inline constexpr double kMilli = 1000.0;  // N -> mN

inline double finite_or(double v, double fallback) { return std::isfinite(v) ? v : fallback; }

// Rotates v by the rotation that takes unit vector `from` onto unit vector `to` (parallel transport).
// Rodrigues' formula with the unnormalised axis a = from x to (|a| = sin, 1 - cos = |a|^2 / (1 + cos)):
// no square root or division by the sine, which the frames call twice per edge and step.
[[gnu::always_inline]] inline glm::dvec3 transport(const glm::dvec3& v, const glm::dvec3& from, const glm::dvec3& to) {
  const glm::dvec3 a = glm::cross(from, to);
  const double s2 = glm::dot(a, a);
  const double c = glm::dot(from, to);
  if (s2 < 1e-28) return v;
  if (c < -0.5) {  // far from parallel: the normalised axis keeps 1 + cos away from a division
    const double s = std::sqrt(s2);
    const glm::dvec3 k = a / s;
    return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0 - c));
  }
  return v * c + glm::cross(a, v) + a * (glm::dot(a, v) / (1.0 + c));
}

inline glm::dvec3 perpendicular_unit(const glm::dvec3& t) {
  const glm::dvec3 a = std::abs(t.x) < 0.6 ? glm::dvec3(1, 0, 0)
                       : std::abs(t.y) < 0.6 ? glm::dvec3(0, 1, 0)
                                              : glm::dvec3(0, 0, 1);
  return glm::normalize(a - t * glm::dot(a, t));
}

// Index of the station holding a distance from the tip (stations descend with k).
inline std::size_t station_at(const std::vector<double>& from_tip, double d) {
  std::size_t lo = 0;
  std::size_t hi = from_tip.size() - 1;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (from_tip[mid] >= d) lo = mid; else hi = mid;
  }
  return lo;
}

// station_at by a walk from `hint` (updated; kNoStation: search): the last index <= size - 2
// whose distance is >= d, or 0 (stations descend strictly).
inline std::size_t station_near(const std::vector<double>& from_tip, double d, std::size_t& hint) {
  if (hint == Rod::kNoStation) {
    hint = station_at(from_tip, d);
    return hint;
  }
  std::size_t k = std::min(hint, from_tip.size() - 2);
  while (k > 0 && from_tip[k] < d) --k;
  while (k + 2 < from_tip.size() && from_tip[k + 1] >= d) ++k;
  hint = k;
  return k;
}

// Rounding of an insertion. Two hands' positions subtracted (an inner tool's protrusion past its
// carrier's tip) are exact only to rounding: a microwire kept 7 mm ahead of its microcatheter,
// both advanced at 10 mm/s, read 7 +- 1.4e-14 mm, and its node 7 mm from the tip went out of the
// clamp and back on 421 ticks in 2.7 s, each release a step that could not converge
// (convergence.md, "A node on the entry").
inline constexpr double kEntrySlack_mm = 1e-6;

// The last node not past the entry (its depth, insertion - from_tip, <= 0); at least 1, so the
// clamp's two nodes exist. While the insertion holds still (within kEntrySlack_mm of the last
// step's), a node within kEntrySlack_mm of the entry is not past it: held on the entry line, not
// let out and taken back on rounding. A moving insertion crosses a node once, as it always did.
inline std::size_t last_outside(const std::vector<double>& from_tip, double insertion_mm, double last_insertion_mm) {
  const double d = std::abs(insertion_mm - last_insertion_mm) <= kEntrySlack_mm ? insertion_mm - kEntrySlack_mm : insertion_mm;
  std::size_t kp = station_at(from_tip, d);
  if (kp + 1 < from_tip.size() && from_tip[kp + 1] >= d) ++kp;
  return std::max<std::size_t>(kp, 1);
}

}  // namespace cathbox::tool::rod_detail

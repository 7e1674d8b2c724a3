#pragma once
// Lumen geometry of a segment between its centreline points, taken as truncated cones (the
// radius varies linearly between points): arc length, volume and Poiseuille resistance.
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "vessel/segment.hpp"

namespace cathbox::flow {

inline constexpr double kPa_per_mmHg = 133.322387415;
// The least resistance a segment is given (Pa.s/mm^3): a zero-length one still conducts finitely.
inline constexpr double kMinResistance = 1e-12;

// Volume of a truncated cone of length L between radii r0 and r1.
[[nodiscard]] inline double cone_volume_mm3(double r0, double r1, double length_mm) {
  return std::numbers::pi * length_mm * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0;
}

// Poiseuille resistance of a truncated cone: the integral of 8 mu / (pi r^4) dx, in Pa.s/mm^3
// for mu in Pa.s and lengths in mm.
[[nodiscard]] inline double cone_resistance(double r0, double r1, double length_mm, double mu_Pa_s) {
  return 8.0 * mu_Pa_s * length_mm * (r0 * r0 + r0 * r1 + r1 * r1) / (3.0 * std::numbers::pi * r0 * r0 * r0 * r1 * r1 * r1);
}

// Arc length at each centreline point (0 at the first).
[[nodiscard]] inline std::vector<double> point_arcs_mm(const vessel::Segment& s) {
  std::vector<double> arc(s.points.size(), 0.0);
  for (std::size_t i = 1; i < s.points.size(); ++i) {
    arc[i] = arc[i - 1] + glm::length(s.points[i].pos_mm - s.points[i - 1].pos_mm);
  }
  return arc;
}

// The centreline piece holding an arc position: piece j (points j and j+1) and the fraction t
// along it, clamped to the segment.
struct ArcPiece {
  std::size_t j = 0;
  double t = 0.0;
};
[[nodiscard]] ArcPiece piece_at(const std::vector<double>& arcs, double arc_mm);

// Radius at an arc position along the segment (linear between points, clamped at the ends).
[[nodiscard]] double radius_at_mm(const vessel::Segment& s, const std::vector<double>& arcs, double arc_mm);

}  // namespace cathbox::flow

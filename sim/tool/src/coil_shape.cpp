#include "tool/coil_shape.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {
constexpr double kArcOfComplexLoop_rad = 1.5 * M_PI;  // three quarters of a circle
constexpr double kComplexTurn_rad = 0.5 * M_PI;       // bending direction step between arcs
}  // namespace

CoilRest coil_rest(const ToolSection& section, double from_tip_mm) {
  CoilRest rest;
  const double d = section.loop_diameter_mm;
  if (section.shape == CoilShape::kNone || !(d > 0.0)) return rest;
  const double r = 0.5 * d;
  const double s = from_tip_mm > 0.0 ? from_tip_mm : 0.0;
  if (section.shape == CoilShape::kHelix) {
    const double c = section.outer_diameter_mm / (2.0 * M_PI);
    rest.curvature_per_mm = r / (r * r + c * c);
    rest.direction_rad = std::fmod(c / (r * r + c * c) * s, 2.0 * M_PI);
  } else {
    rest.curvature_per_mm = 1.0 / r;
    const double arc = kArcOfComplexLoop_rad * r;
    rest.direction_rad = std::fmod(std::floor(s / arc) * kComplexTurn_rad, 2.0 * M_PI);
  }
  return rest;
}

double coil_loop_diameter_mm(const ToolSection& section) {
  return section.shape == CoilShape::kNone ? 0.0 : section.loop_diameter_mm;
}

std::vector<glm::dvec3> coil_rest_curve(const ToolSection& section, double length_mm, double step_mm) {
  std::vector<glm::dvec3> points;
  if (!(step_mm > 0.0) || !(length_mm > 0.0)) return points;
  glm::dvec3 p(0.0), t(0, 0, 1), m1(1, 0, 0);
  points.push_back(p);
  for (double s = 0.0; s < length_mm; s += step_mm) {
    const CoilRest rest = coil_rest(section, s + 0.5 * step_mm);
    const glm::dvec3 m2 = glm::cross(t, m1);
    const glm::dvec3 towards = m1 * std::cos(rest.direction_rad) + m2 * std::sin(rest.direction_rad);
    // Rotate the tangent (and the frame with it) by the turning angle about the binormal.
    const double phi = rest.curvature_per_mm * step_mm;
    const glm::dvec3 t_new = glm::normalize(t * std::cos(phi) + towards * std::sin(phi));
    p += (t + t_new) * (0.5 * step_mm);
    // Parallel transport of m1 from t to t_new.
    const glm::dvec3 axis = glm::cross(t, t_new);
    const double sa = glm::length(axis);
    if (sa > 1e-14) {
      const glm::dvec3 k = axis / sa;
      const double ca = glm::dot(t, t_new);
      m1 = m1 * ca + glm::cross(k, m1) * sa + k * (glm::dot(k, m1) * (1.0 - ca));
      m1 = glm::normalize(m1 - t_new * glm::dot(m1, t_new));
    }
    t = t_new;
    points.push_back(p);
  }
  return points;
}

}  // namespace cathbox::tool

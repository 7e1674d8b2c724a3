#include "vessel/rotation_minimizing_frame.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::vessel {
namespace {

[[nodiscard]] glm::dvec3 orthonormalize(const glm::dvec3& r, const glm::dvec3& t) {
  const glm::dvec3 v = r - glm::dot(r, t) * t;
  const double len = glm::length(v);
  return len > 1e-12 ? v / len : any_perpendicular(t);
}

// Rotation taking unit a onto unit b by the smallest angle, applied to v (Rodrigues).
[[nodiscard]] glm::dvec3 rotate_between(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& v) {
  const glm::dvec3 axis = glm::cross(a, b);
  const double s = glm::length(axis);
  const double c = glm::dot(a, b);
  if (s < 1e-14) return c > 0.0 ? v : v - 2.0 * glm::dot(v, a) * a;  // identity / half turn
  const glm::dvec3 k = axis / s;
  return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0 - c);
}

}  // namespace

glm::dvec3 any_perpendicular(const glm::dvec3& t) {
  const glm::dvec3 a = std::abs(t.x) <= std::abs(t.y) && std::abs(t.x) <= std::abs(t.z) ? glm::dvec3(1, 0, 0)
                       : std::abs(t.y) <= std::abs(t.z)                                 ? glm::dvec3(0, 1, 0)
                                                                                          : glm::dvec3(0, 0, 1);
  return glm::normalize(glm::cross(t, a));
}

glm::dvec3 transport_normal(const glm::dvec3& x0, const glm::dvec3& t0, const glm::dvec3& r0, const glm::dvec3& x1,
                            const glm::dvec3& t1) {
  // Reflection 1 in the bisecting plane of x0 and x1.
  const glm::dvec3 v1 = x1 - x0;
  const double c1 = glm::dot(v1, v1);
  glm::dvec3 r_l = r0;
  glm::dvec3 t_l = t0;
  if (c1 > 1e-24) {
    r_l = r0 - (2.0 / c1) * glm::dot(v1, r0) * v1;
    t_l = t0 - (2.0 / c1) * glm::dot(v1, t0) * v1;
  }
  // Reflection 2 taking the reflected tangent onto t1.
  const glm::dvec3 v2 = t1 - t_l;
  const double c2 = glm::dot(v2, v2);
  glm::dvec3 r1 = r_l;
  if (c2 > 1e-24) r1 = r_l - (2.0 / c2) * glm::dot(v2, r_l) * v2;
  return orthonormalize(r1, t1);
}

double twist_angle_rad(const glm::dvec3& t0, const glm::dvec3& r0, const glm::dvec3& t1, const glm::dvec3& r1) {
  const glm::dvec3 moved = orthonormalize(rotate_between(t0, t1, r0), t1);
  const double sin_a = glm::dot(glm::cross(moved, r1), t1);
  const double cos_a = glm::dot(moved, r1);
  return std::atan2(sin_a, cos_a);
}

}  // namespace cathbox::vessel

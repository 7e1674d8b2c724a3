#pragma once
// Rotation-minimising frames by the double reflection method (Wang, Juettler, Zheng, Liu,
// "Computation of rotation minimizing frames", ACM TOG 27(1), 2008). Transporting the ring
// frame this way from ring to ring keeps cross sections from twisting (thesis 3.4.1).
#include <glm/vec3.hpp>

namespace cathbox::vessel {

// Transports the unit normal r0 (perpendicular to the unit tangent t0 at x0) to the point x1
// with unit tangent t1. The result is a unit vector perpendicular to t1.
[[nodiscard]] glm::dvec3 transport_normal(const glm::dvec3& x0, const glm::dvec3& t0, const glm::dvec3& r0,
                                          const glm::dvec3& x1, const glm::dvec3& t1);

// A unit vector perpendicular to the unit vector t (deterministic).
[[nodiscard]] glm::dvec3 any_perpendicular(const glm::dvec3& t);

// Rotation about t1 that takes r0, moved by the smallest rotation from t0 to t1, onto r1
// (radians, in [-pi, pi]). Zero for a twist-free frame pair.
[[nodiscard]] double twist_angle_rad(const glm::dvec3& t0, const glm::dvec3& r0, const glm::dvec3& t1,
                                     const glm::dvec3& r1);

}  // namespace cathbox::vessel

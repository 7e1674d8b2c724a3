#pragma once
// Analytic lumens for the rod validation tests: a straight tube, a circular bend, a Y, a sphere
// on a tube.
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "tool/tube_network_wall.hpp"

namespace cathbox::tool::testing {

class NoWall final : public WallModel {
 public:
  [[nodiscard]] bool probe(const WallProbe&, WallHint&, WallContact&) const override { return false; }
};

// The plane {x : normal . x = offset} as the wall a probe meets (normal unit, out of the lumen);
// false beyond the probe's range. For the test walls made of planes.
inline bool plane_contact(const WallProbe& p, const glm::dvec3& normal, double offset, WallContact& out) {
  const double d = offset - glm::dot(normal, p.center_mm);
  if (d - p.radius_mm > p.range_mm) return false;
  out.normal = normal;
  out.distance_mm = d;
  out.point_mm = p.center_mm + normal * d;
  out.segment = 0;
  return true;
}

// Straight tube along +z from z0 to z1.
inline TubeNetworkWall straight_tube(double radius_mm, double z0, double z1) {
  return TubeNetworkWall({Tube{{0, 0, z0}, {0, 0, z1}, radius_mm, radius_mm, 0}});
}

// Points of a circular bend in the x-z plane starting at the origin along +z, bending towards
// +x with bend radius R over angle_rad, then `lead_out` mm straight. Lead-in of `lead_in` mm.
inline std::vector<glm::dvec3> bend_points(double R, double angle_rad, double lead_in, double lead_out,
                                           double step_rad = M_PI / 360.0) {
  std::vector<glm::dvec3> pts;
  pts.push_back({0, 0, -lead_in});
  const int n = std::max(1, static_cast<int>(std::ceil(angle_rad / step_rad)));
  for (int i = 0; i <= n; ++i) {
    const double a = angle_rad * i / n;
    pts.push_back({R - R * std::cos(a), 0, R * std::sin(a)});
  }
  const glm::dvec3 t{std::sin(angle_rad), 0, std::cos(angle_rad)};
  pts.push_back(pts.back() + t * lead_out);
  return pts;
}

inline glm::dvec3 bend_exit_tangent(double angle_rad) { return {std::sin(angle_rad), 0, std::cos(angle_rad)}; }

// A Y: parent along +z ending at the origin, children to (+-dx, 0, dz) (segments 1 and 2).
inline TubeNetworkWall y_bifurcation(double parent_r = 1.5, double child_r = 1.2, double dx = 12.0,
                                     double dz = 30.0) {
  return TubeNetworkWall({Tube{{0, 0, -45}, {0, 0, 0}, parent_r, parent_r, 0},
                          Tube{{0, 0, 0}, {dx, 0, dz}, parent_r, child_r, 1},
                          Tube{{0, 0, 0}, {-dx, 0, dz}, parent_r, child_r, 2}});
}

// The bundled sac as a free sphere: the dome radius of the sphere of its volume (~3.2 mm), a 1 mm
// neck, 20 mm up the parent artery.
inline constexpr double kSacSphereR = 3.2;
inline constexpr double kSacNeckR = 1.0;
inline const glm::dvec3 kSacCentre(0.0, 0.0, 20.0);

// A free sphere (the sac; segment 1) centred at `centre`, opened by a parent artery of radius
// neck_r along +z from z = -5 (segment 0): the coiling tests' analytic aneurysm.
inline TubeNetworkWall sphere_on_a_tube(double sphere_r, double neck_r, const glm::dvec3& centre) {
  TubeNetworkWall wall;
  wall.add_tube(Tube{{0, 0, -5}, centre, neck_r, neck_r, 0});
  wall.add_tube(Tube{centre, centre + glm::dvec3(0, 0, 1e-3), sphere_r, sphere_r, 1});
  wall.build();
  return wall;
}

}  // namespace cathbox::tool::testing

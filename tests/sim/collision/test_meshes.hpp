#pragma once
// Meshes and random query points shared by the collision tests.
#include <limits>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "brute_force.hpp"
#include "collision/obb_tree.hpp"
#include "mesh_factory.hpp"

namespace cathbox::collision::testing {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct NamedMesh {
  const char* name;
  vessel::SurfaceMesh mesh;
  bool closed;
};

inline std::vector<NamedMesh> exactness_meshes() {
  std::vector<NamedMesh> out;
  out.push_back({"soup", make_soup(1500, 7), false});
  out.push_back({"bumpy_sphere", make_bumpy_sphere(40, 60, 5.0, 0.08, 11), true});
  out.push_back({"knot_tube", make_knot_tube(300, 16), true});
  TubeSpec bent;
  bent.centerline = [](double s) { return glm::dvec3{30.0 * s, 8.0 * std::sin(4.0 * s), 3.0 * s * s}; };
  bent.radius_mm = [](double s) { return 2.0 - 1.2 * s; };
  bent.rings = 120;
  bent.sides = 12;
  bent.segments = 6;
  bent.junction_every = 3;
  out.push_back({"tapered_tube", make_tube(bent), true});
  return out;
}

// A random point on a random non-degenerate triangle.
inline glm::dvec3 random_surface_point(const vessel::SurfaceMesh& m, std::mt19937& rng, std::size_t* face = nullptr) {
  std::uniform_int_distribution<std::size_t> pick(0, m.triangle_count() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t t = pick(rng);
  while (is_degenerate(m, t)) t = pick(rng);
  double a = u(rng), b = u(rng);
  if (a + b > 1.0) {
    a = 1.0 - a;
    b = 1.0 - b;
  }
  if (face) *face = t;
  return corner(m, t, 0) + a * (corner(m, t, 1) - corner(m, t, 0)) + b * (corner(m, t, 2) - corner(m, t, 0));
}

inline glm::dvec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  glm::dvec3 v{g(rng), g(rng), g(rng)};
  return glm::normalize(v);
}

// Points near the wall (within `spread` mm, both sides) and far from it (in a box twice the size).
inline std::vector<glm::dvec3> query_points(const vessel::SurfaceMesh& m, int count, double spread, std::uint32_t seed) {
  std::mt19937 rng(seed);
  glm::dvec3 lo{1e30}, hi{-1e30};
  for (const auto& p : m.positions_mm) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  const glm::dvec3 c = (lo + hi) * 0.5;
  const glm::dvec3 h = (hi - lo);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> r(0.0, spread);
  std::vector<glm::dvec3> out;
  for (int i = 0; i < count; ++i) {
    if (i % 4 == 3) {
      out.push_back(c + glm::dvec3{u(rng) * h.x, u(rng) * h.y, u(rng) * h.z});
    } else {
      out.push_back(random_surface_point(m, rng) + r(rng) * random_unit(rng));
    }
  }
  return out;
}

inline bool near_rel(double got, double want, double rel = 1e-6, double abs = 1e-9) {
  return std::abs(got - want) <= rel * std::abs(want) + abs;
}

}  // namespace cathbox::collision::testing

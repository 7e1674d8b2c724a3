#include "mesh_factory.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <utility>

#include <glm/geometric.hpp>

namespace cathbox::collision::testing {

namespace {

void add_triangle(vessel::SurfaceMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c,
                  vessel::FaceRegion region) {
  m.triangles.insert(m.triangles.end(), {a, b, c});
  m.triangle_regions.push_back(region);
}

std::uint32_t add_vertex(vessel::SurfaceMesh& m, const glm::dvec3& p) {
  m.positions_mm.emplace_back(p);
  return static_cast<std::uint32_t>(m.positions_mm.size() - 1);
}

void fill_vertex_normals(vessel::SurfaceMesh& m) {
  std::vector<glm::dvec3> acc(m.positions_mm.size(), glm::dvec3{0.0});
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const glm::dvec3 a(m.positions_mm[m.triangles[3 * t]]);
    const glm::dvec3 b(m.positions_mm[m.triangles[3 * t + 1]]);
    const glm::dvec3 c(m.positions_mm[m.triangles[3 * t + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    for (int k = 0; k < 3; ++k) acc[m.triangles[3 * t + k]] += n;
  }
  m.normals.resize(acc.size());
  for (std::size_t i = 0; i < acc.size(); ++i) {
    const double len = glm::length(acc[i]);
    m.normals[i] = len > 0.0 ? glm::vec3(acc[i] / len) : glm::vec3(0.0f, 0.0f, 1.0f);
  }
}

}  // namespace

void orient_outward(vessel::SurfaceMesh& m) {
  double volume = 0.0;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const glm::dvec3 a(m.positions_mm[m.triangles[3 * t]]);
    const glm::dvec3 b(m.positions_mm[m.triangles[3 * t + 1]]);
    const glm::dvec3 c(m.positions_mm[m.triangles[3 * t + 2]]);
    volume += glm::dot(a, glm::cross(b, c));
  }
  if (volume < 0.0)
    for (std::size_t t = 0; t < m.triangle_count(); ++t) std::swap(m.triangles[3 * t + 1], m.triangles[3 * t + 2]);
  fill_vertex_normals(m);
}

vessel::SurfaceMesh make_tube(const TubeSpec& spec) {
  vessel::SurfaceMesh m;
  const int rings = spec.rings;
  const int sides = spec.sides;
  // Parallel-transport frames along the centreline.
  glm::dvec3 prev_t = glm::normalize(spec.centerline(1e-4) - spec.centerline(0.0));
  glm::dvec3 n = std::abs(prev_t.x) < 0.9 ? glm::dvec3{1, 0, 0} : glm::dvec3{0, 1, 0};
  n = glm::normalize(n - glm::dot(n, prev_t) * prev_t);
  for (int i = 0; i < rings; ++i) {
    const double s = static_cast<double>(i) / (rings - 1);
    const double s0 = std::max(0.0, s - 1e-4);
    const double s1 = std::min(1.0, s + 1e-4);
    const glm::dvec3 t = glm::normalize(spec.centerline(s1) - spec.centerline(s0));
    n = glm::normalize(n - glm::dot(n, t) * t);
    const glm::dvec3 b = glm::cross(t, n);
    const glm::dvec3 c = spec.centerline(s);
    const double r = spec.radius_mm(s);
    for (int j = 0; j < sides; ++j) {
      const double a = 2.0 * std::numbers::pi * j / sides;
      add_vertex(m, c + r * (std::cos(a) * n + std::sin(a) * b));
    }
    prev_t = t;
  }
  auto vid = [&](int i, int j) { return static_cast<std::uint32_t>(i * sides + (j % sides)); };
  for (int i = 0; i + 1 < rings; ++i) {
    int seg = i * spec.segments / (rings - 1);
    vessel::FaceRegion region{vessel::RegionKind::kSegment, seg};
    if (spec.junction_every > 0 && seg % spec.junction_every == spec.junction_every - 1)
      region.kind = vessel::RegionKind::kJunction;
    for (int j = 0; j < sides; ++j) {
      add_triangle(m, vid(i, j), vid(i, j + 1), vid(i + 1, j + 1), region);
      add_triangle(m, vid(i, j), vid(i + 1, j + 1), vid(i + 1, j), region);
    }
  }
  const std::uint32_t c0 = add_vertex(m, spec.centerline(0.0));
  const std::uint32_t c1 = add_vertex(m, spec.centerline(1.0));
  for (int j = 0; j < sides; ++j) {
    add_triangle(m, c0, vid(0, j + 1), vid(0, j), {vessel::RegionKind::kCap, 0});
    add_triangle(m, c1, vid(rings - 1, j), vid(rings - 1, j + 1), {vessel::RegionKind::kCap, spec.segments - 1});
  }
  orient_outward(m);
  return m;
}

vessel::SurfaceMesh make_knot_tube(int rings, int sides) {
  TubeSpec spec;
  spec.centerline = [](double s) {
    const double phi = s * 0.95 * 2.0 * std::numbers::pi;
    const double r = 40.0 + 15.0 * std::cos(3.0 * phi);
    return glm::dvec3{r * std::cos(2.0 * phi), r * std::sin(2.0 * phi), -15.0 * std::sin(3.0 * phi)};
  };
  spec.radius_mm = [](double s) { return 1.5 + 0.5 * std::sin(9.0 * s); };
  spec.rings = rings;
  spec.sides = sides;
  spec.segments = 40;
  spec.junction_every = 5;
  return make_tube(spec);
}

vessel::SurfaceMesh make_bumpy_sphere(int stacks, int slices, double radius_mm, double noise,
                                      std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  vessel::SurfaceMesh m;
  const std::uint32_t top = add_vertex(m, {0, 0, radius_mm * (1.0 + jitter(rng))});
  for (int i = 1; i < stacks; ++i) {
    const double th = std::numbers::pi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double ph = 2.0 * std::numbers::pi * j / slices;
      const double r = radius_mm * (1.0 + jitter(rng));
      add_vertex(m, {r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)});
    }
  }
  const std::uint32_t bottom = add_vertex(m, {0, 0, -radius_mm * (1.0 + jitter(rng))});
  auto vid = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * slices + (j % slices)); };
  auto region = [&](int i, int j) {
    return vessel::FaceRegion{(i < stacks / 2) ? vessel::RegionKind::kSegment : vessel::RegionKind::kJunction,
                              4 * j / slices};
  };
  for (int j = 0; j < slices; ++j) add_triangle(m, top, vid(1, j), vid(1, j + 1), region(0, j));
  for (int i = 1; i + 1 < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      add_triangle(m, vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), region(i, j));
      add_triangle(m, vid(i, j), vid(i + 1, j + 1), vid(i, j + 1), region(i, j));
    }
  for (int j = 0; j < slices; ++j)
    add_triangle(m, bottom, vid(stacks - 1, j + 1), vid(stacks - 1, j), {vessel::RegionKind::kCap, 1});
  orient_outward(m);
  return m;
}

vessel::SurfaceMesh make_soup(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-10.0, 10.0);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> size(0.05, 3.0);
  vessel::SurfaceMesh m;
  for (int t = 0; t < n; ++t) {
    const glm::dvec3 c{pos(rng), pos(rng), pos(rng)};
    const double s = size(rng);
    glm::dvec3 p[3];
    for (auto& q : p) q = c + s * glm::dvec3{unit(rng), unit(rng), unit(rng)};
    if (t % 17 == 3) p[2] = p[0] + 1e-7 * (p[1] - p[0]) + glm::dvec3{0, 0, 1e-9};  // sliver
    if (t % 29 == 5) p[2] = p[1];                                                 // degenerate
    if (t % 31 == 7) p[2] = 0.5 * (p[0] + p[1]);                                  // collinear
    const std::uint32_t base = static_cast<std::uint32_t>(m.positions_mm.size());
    for (const auto& q : p) add_vertex(m, q);
    add_triangle(m, base, base + 1, base + 2, {vessel::RegionKind::kSegment, t % 7});
  }
  fill_vertex_normals(m);
  return m;
}

}  // namespace cathbox::collision::testing

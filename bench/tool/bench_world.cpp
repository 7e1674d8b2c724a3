#include "bench_world.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>

#include "collision/obb_tree.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "tool/mesh_wall.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::bench {
namespace {

using namespace cathbox::tool;

// A tortuous path of neuro-like size: 500 mm from a wide proximal vessel to a narrow distal one.
std::vector<glm::dvec3> tortuous_axis() {
  std::vector<glm::dvec3> pts;
  glm::dvec3 p(0.0);
  for (int i = 0; i <= 1000; ++i) {
    const double s = i * 0.5;
    const double bend = 0.6 * std::sin(s / 25.0) + 0.3 * std::sin(s / 9.0);
    const glm::dvec3 t = glm::normalize(glm::dvec3(std::sin(bend), 0.4 * std::sin(s / 15.0), std::cos(bend)));
    pts.push_back(p);
    p += t * 0.5;
  }
  return pts;
}

}  // namespace

World make_world() {
  World w;
  const CaseParse c = load_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.case");
  if (c) {
    WorldBuild built = build_world(*c);
    if (built) {
      w.entry = (*built)->entry();
      w.wall = (*built)->release_wall();
      w.name = "neuro case";
      return w;
    }
  }
  const std::vector<glm::dvec3> axis = tortuous_axis();
  // Meshed tube, radius from 3 mm down to 1.5 mm, through the collision tree.
  cathbox::vessel::SurfaceMesh mesh;
  const int m = 16;
  glm::dvec3 u_prev(1, 0, 0);
  for (std::size_t i = 0; i < axis.size(); ++i) {
    const glm::dvec3 t = glm::normalize(i + 1 < axis.size() ? axis[i + 1] - axis[i] : axis[i] - axis[i - 1]);
    glm::dvec3 u = glm::normalize(u_prev - t * glm::dot(u_prev, t));
    u_prev = u;
    const glm::dvec3 v = glm::cross(t, u);
    const double r = 4.0 - 2.5 * static_cast<double>(i) / static_cast<double>(axis.size());
    for (int j = 0; j < m; ++j) {
      const double a = 2.0 * M_PI * j / m;
      const glm::dvec3 d = u * std::cos(a) + v * std::sin(a);
      mesh.positions_mm.push_back(glm::vec3(axis[i] + d * r));
      mesh.normals.push_back(glm::vec3(d));
    }
  }
  auto idx = [&](std::size_t ring, int j) { return static_cast<std::uint32_t>(ring * m + (j % m)); };
  auto tri = [&](std::uint32_t i0, std::uint32_t i1, std::uint32_t i2) {
    mesh.triangles.insert(mesh.triangles.end(), {i0, i1, i2});
    mesh.triangle_regions.push_back({cathbox::vessel::RegionKind::kSegment, 0});
  };
  for (std::size_t i = 0; i + 1 < axis.size(); ++i) {
    for (int j = 0; j < m; ++j) {
      tri(idx(i, j), idx(i, j + 1), idx(i + 1, j + 1));
      tri(idx(i, j), idx(i + 1, j + 1), idx(i + 1, j));
    }
  }
  const auto c0 = static_cast<std::uint32_t>(mesh.positions_mm.size());
  mesh.positions_mm.push_back(glm::vec3(axis.front()));
  mesh.normals.push_back({0, 0, -1});
  const auto c1 = static_cast<std::uint32_t>(mesh.positions_mm.size());
  mesh.positions_mm.push_back(glm::vec3(axis.back()));
  mesh.normals.push_back({0, 0, 1});
  const std::size_t last = axis.size() - 1;
  for (int j = 0; j < m; ++j) {
    tri(c0, idx(0, j + 1), idx(0, j));
    tri(c1, idx(last, j), idx(last, j + 1));
  }
  cathbox::collision::TreeBuild tree = cathbox::collision::ObbTree::build(mesh);
  if (tree) {
    w.wall = std::make_unique<MeshWall>(*tree);
    w.entry = Entry{axis[2], glm::normalize(axis[3] - axis[2])};
    w.name = "tortuous tube mesh";
    return w;
  }
  auto tubes = std::make_unique<TubeNetworkWall>();
  tubes->add_polyline(axis, 2.0, 0);
  tubes->build();
  w.wall = std::move(tubes);
  w.entry = Entry{axis[2], glm::normalize(axis[3] - axis[2])};
  w.name = "tortuous analytic tube";
  return w;
}

}  // namespace cathbox::bench

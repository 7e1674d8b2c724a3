#include "vessel/mesh_analysis.hpp"

#include <glm/geometric.hpp>
#include <cmath>

#include <gtest/gtest.h>

namespace cathbox::vessel {
namespace {

SurfaceMesh tetrahedron() {
  SurfaceMesh m;
  m.positions_mm = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
  m.triangle_regions.resize(4);
  return m;
}

// A torus as a quad grid split into triangles: Euler characteristic 0.
SurfaceMesh torus(int nu, int nv) {
  SurfaceMesh m;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * 3.14159265358979 * i / nu;
      const double v = 2 * 3.14159265358979 * j / nv;
      m.positions_mm.emplace_back((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  }
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  m.triangle_regions.resize(m.triangles.size() / 3);
  return m;
}

TEST(MeshAnalysis, ClosedTetrahedron) {
  const MeshAnalysis a = analyze_mesh(tetrahedron());
  EXPECT_TRUE(a.closed());
  EXPECT_TRUE(a.manifold());
  EXPECT_TRUE(a.consistently_oriented());
  EXPECT_EQ(a.edges, 6u);
  EXPECT_EQ(a.euler_characteristic, 2);
  EXPECT_NEAR(a.signed_volume_mm3, 1.0 / 6.0, 1e-9);
}

TEST(MeshAnalysis, DetectsHolesFlipsAndNonManifoldEdges) {
  SurfaceMesh open = tetrahedron();
  open.triangles.resize(9);
  EXPECT_EQ(analyze_mesh(open).boundary_edges, 3u);

  SurfaceMesh flipped = tetrahedron();
  std::swap(flipped.triangles[0], flipped.triangles[1]);
  EXPECT_EQ(analyze_mesh(flipped).misoriented_edges, 3u);

  SurfaceMesh fin = tetrahedron();
  fin.positions_mm.push_back({1, 1, 1});
  fin.triangles.insert(fin.triangles.end(), {1, 2, 4});
  EXPECT_EQ(analyze_mesh(fin).nonmanifold_edges, 1u);

  // Two tetrahedra sharing one vertex: every edge is fine, the vertex is not.
  SurfaceMesh bowtie = tetrahedron();
  for (const glm::vec3& p : tetrahedron().positions_mm) bowtie.positions_mm.push_back(-p);
  for (std::uint32_t v : tetrahedron().triangles) bowtie.triangles.push_back(v == 0 ? 0 : v + 4);
  const MeshAnalysis b = analyze_mesh(bowtie);
  EXPECT_EQ(b.nonmanifold_edges, 0u);
  EXPECT_EQ(b.nonmanifold_vertices, 1u);
}

TEST(MeshAnalysis, TorusHasEulerCharacteristicZero) {
  const MeshAnalysis a = analyze_mesh(torus(24, 12));
  EXPECT_TRUE(a.closed() && a.manifold() && a.consistently_oriented());
  EXPECT_EQ(a.euler_characteristic, 0);
  EXPECT_EQ(count_self_intersections(torus(24, 12)), 0u);
}

TEST(MeshAnalysis, FindsCrossingTriangles) {
  SurfaceMesh m;
  m.positions_mm = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {1.5, 1.5, 1}};
  m.triangles = {0, 1, 2, 3, 4, 5};
  m.triangle_regions.resize(2);
  EXPECT_EQ(count_self_intersections(m), 1u);
  m.positions_mm[3] = {0.5, 0.5, 0.2};  // lifted clear of the first triangle
  EXPECT_EQ(count_self_intersections(m), 0u);
}

}  // namespace
}  // namespace cathbox::vessel

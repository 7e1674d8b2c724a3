#include "vessel/mesh_analysis.hpp"

#include <glm/geometric.hpp>
#include <cmath>

#include <gtest/gtest.h>

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "vessel/case_generator.hpp"
#include "vessel/vessel_mesher.hpp"
#include "reference_mesh_analysis.hpp"

namespace cathbox::vessel {
namespace {

void expect_same_analysis(const SurfaceMesh& mesh, const std::string& what) {
  const MeshAnalysis a = analyze_mesh(mesh);
  const MeshAnalysis r = test::reference_analysis(mesh);
  EXPECT_EQ(a.vertices, r.vertices) << what;
  EXPECT_EQ(a.edges, r.edges) << what;
  EXPECT_EQ(a.triangles, r.triangles) << what;
  EXPECT_EQ(a.boundary_edges, r.boundary_edges) << what;
  EXPECT_EQ(a.nonmanifold_edges, r.nonmanifold_edges) << what;
  EXPECT_EQ(a.misoriented_edges, r.misoriented_edges) << what;
  EXPECT_EQ(a.nonmanifold_vertices, r.nonmanifold_vertices) << what;
  EXPECT_EQ(a.degenerate_triangles, r.degenerate_triangles) << what;
  EXPECT_EQ(a.euler_characteristic, r.euler_characteristic) << what;
  EXPECT_EQ(a.signed_volume_mm3, r.signed_volume_mm3) << what;
  EXPECT_EQ(a.area_mm2, r.area_mm2) << what;
}

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

TEST(MeshAnalysis, AgreesWithTheReferenceOnGoodAndBrokenMeshes) {
  std::vector<std::pair<std::string, SurfaceMesh>> meshes;
  meshes.emplace_back("tetrahedron", tetrahedron());
  meshes.emplace_back("torus", torus(24, 12));
  for (const std::string& name : {std::string("y_bifurcation"), std::string("neuro_aneurysm")}) {
    const VesselSurface surface = build_vessel_surface(CaseGenerator::make_case(name));
    ASSERT_TRUE(surface.ok()) << surface.error;
    meshes.emplace_back(name, surface.mesh);
  }
  MeshOptions open_ends;
  open_ends.caps = false;
  meshes.emplace_back("random graph, open ends", build_vessel_surface(CaseGenerator::random_graph(3, 2), open_ends).mesh);
  // Broken copies: holes, flipped and doubled triangles, fins, pinched vertices, degenerate ones.
  const std::size_t originals = meshes.size();
  for (std::size_t i = 0; i < originals; ++i) {
    SurfaceMesh broken = meshes[i].second;
    auto& t = broken.triangles;
    std::uint64_t state = 12345 + i;
    const auto pick = [&](std::size_t n) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return static_cast<std::size_t>((state >> 33) % n);
    };
    for (int k = 0; k < 6; ++k) {
      const std::size_t f = 3 * pick(t.size() / 3);
      switch (k % 6) {
        case 0: t.erase(t.begin() + static_cast<std::ptrdiff_t>(f), t.begin() + static_cast<std::ptrdiff_t>(f + 3)); break;
        case 1: std::swap(t[f], t[f + 1]); break;
        case 2: t.insert(t.end(), {t[f], t[f + 1], t[f + 2]}); break;
        case 3: t.insert(t.end(), {t[f], t[f + 1], t[3 * pick(t.size() / 3)]}); break;
        case 4: t[f + 2] = t[f]; break;
        default: t[f + 1] = t[3 * pick(t.size() / 3) + 1]; break;
      }
    }
    broken.triangle_regions.resize(t.size() / 3);
    meshes.emplace_back(meshes[i].first + ", broken", std::move(broken));
  }
  MeshAnalysis problems;  // the broken copies must show every kind of problem
  for (const auto& [name, mesh] : meshes) {
    expect_same_analysis(mesh, name);
    const MeshAnalysis a = analyze_mesh(mesh);
    problems.boundary_edges += a.boundary_edges;
    problems.misoriented_edges += a.misoriented_edges;
    problems.nonmanifold_edges += a.nonmanifold_edges;
    problems.nonmanifold_vertices += a.nonmanifold_vertices;
    problems.degenerate_triangles += a.degenerate_triangles;
  }
  EXPECT_GT(problems.boundary_edges, 0u);
  EXPECT_GT(problems.misoriented_edges, 0u);
  EXPECT_GT(problems.nonmanifold_edges, 0u);
  EXPECT_GT(problems.nonmanifold_vertices, 0u);
  EXPECT_GT(problems.degenerate_triangles, 0u);
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

#pragma once
// Shared helpers of the vessel tests: paths of bundled cases and the checks every surface must pass.
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "vessel/mesh_analysis.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::vessel::test {

inline std::string case_path(const std::string& name) {
  return std::string(CATHBOX_SOURCE_DIR) + "/cases/" + name + ".hclm";
}

// Closed (or open with boundary only when caps are off), manifold, consistently oriented outward,
// the expected Euler characteristic, unit normals agreeing with the faces, valid regions.
inline void expect_valid_surface(const VesselSurface& surface, const VesselModel& model, bool caps = true) {
  ASSERT_TRUE(surface.ok()) << surface.error;
  const SurfaceMesh& mesh = surface.mesh;
  const MeshAnalysis a = analyze_mesh(mesh);
  if (caps) {
    EXPECT_TRUE(a.closed()) << a.boundary_edges << " boundary edges";
  }
  EXPECT_TRUE(a.manifold()) << a.nonmanifold_edges << " non-manifold edges, " << a.nonmanifold_vertices
                            << " non-manifold vertices";
  EXPECT_TRUE(a.consistently_oriented()) << a.misoriented_edges << " misoriented edges";
  EXPECT_EQ(a.degenerate_triangles, 0u);
  EXPECT_EQ(a.euler_characteristic, surface.euler_characteristic);
  if (caps) {
    EXPECT_GT(a.signed_volume_mm3, 0.0) << "surface is oriented inward";
  }
  ASSERT_EQ(mesh.normals.size(), mesh.positions_mm.size());
  ASSERT_EQ(mesh.triangle_regions.size(), mesh.triangle_count());
  // Normals: unit, and on the outer side of every triangle that uses the vertex.
  std::size_t disagreeing = 0;
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const glm::vec3& p0 = mesh.positions_mm[mesh.triangles[3 * f]];
    const glm::vec3 n = glm::cross(mesh.positions_mm[mesh.triangles[3 * f + 1]] - p0,
                                   mesh.positions_mm[mesh.triangles[3 * f + 2]] - p0);
    for (int k = 0; k < 3; ++k) {
      if (glm::dot(n, mesh.normals[mesh.triangles[3 * f + static_cast<std::size_t>(k)]]) <= 0.0f) ++disagreeing;
    }
  }
  EXPECT_EQ(disagreeing, 0u) << "vertex normals pointing against their faces";
  for (const glm::vec3& n : mesh.normals) {
    ASSERT_NEAR(glm::length(n), 1.0f, 1e-3f);
  }
  for (const FaceRegion& r : mesh.triangle_regions) {
    if (r.kind == RegionKind::kJunction) {
      ASSERT_GE(r.id, 0);
    } else {
      ASSERT_TRUE(model.index_of(r.id).has_value()) << "region names unknown segment " << r.id;
    }
  }
}

}  // namespace cathbox::vessel::test

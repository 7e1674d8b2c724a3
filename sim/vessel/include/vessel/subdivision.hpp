#pragma once
// Catmull-Clark subdivision of the control mesh with OpenSubdiv (Far::TopologyRefiner, uniform
// refinement, Far::PrimvarRefiner for positions and limit positions/normals). The result is the
// refined mesh's vertices moved to the limit surface, each quad split into two triangles.
#include <string>

#include "vessel/control_mesh.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::vessel {

struct SurfaceMeshResult {
  SurfaceMesh mesh;
  std::string error;  // empty on success
  [[nodiscard]] bool ok() const { return error.empty(); }
};

// level 0 returns the control mesh itself, triangulated (normals from the faces).
[[nodiscard]] SurfaceMeshResult subdivide(const ControlMesh& control, int level);

}  // namespace cathbox::vessel

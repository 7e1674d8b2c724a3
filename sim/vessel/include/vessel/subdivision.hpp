#pragma once
// Catmull-Clark subdivision of the control mesh with OpenSubdiv (Far::TopologyRefiner, uniform
// refinement, Far::PrimvarRefiner for the refined positions, then limit positions and normals).
// The result is the refined mesh's vertices moved to the limit surface, each quad split into two
// triangles along its shorter diagonal.
#include <string>

#include "vessel/control_mesh.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::vessel {

struct SurfaceMeshResult {
  SurfaceMesh mesh;
  std::string error;  // empty on success
  [[nodiscard]] bool ok() const { return error.empty(); }
};

// How the refined vertices are moved to the limit surface:
//  kMasks: the Catmull-Clark limit position and tangent masks (Halstead et al. 1993) applied to
//          the last level, whose faces are all quads (fast: the refiner skips the last level's
//          full topology). Cross-checked against kOpenSubdiv in the tests.
//  kOpenSubdiv: Far::PrimvarRefiner::Limit() with full topology in the last level.
enum class LimitMethod { kMasks, kOpenSubdiv };

// level 0 returns the control mesh itself, triangulated (normals from the faces).
[[nodiscard]] SurfaceMeshResult subdivide(const ControlMesh& control, int level,
                                          LimitMethod method = LimitMethod::kMasks);

}  // namespace cathbox::vessel

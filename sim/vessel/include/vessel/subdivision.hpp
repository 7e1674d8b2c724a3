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
//          the last level. OpenSubdiv refines to level L-1; on a closed mesh without creases
//          the last step is done with PrimvarRefiner's own smooth weights in the same order
//          straight into the limit pass (so OpenSubdiv never builds level L), otherwise as
//          kMasksOnRefinedLevel. Cross-checked against the other two in the tests.
//  kMasksOnRefinedLevel: the same masks on level L as OpenSubdiv refines it (faces only) and
//          PrimvarRefiner interpolates it; kMasks must give exactly this mesh.
//  kOpenSubdiv: Far::PrimvarRefiner::Limit() with full topology in the last level.
enum class LimitMethod { kMasks, kMasksOnRefinedLevel, kOpenSubdiv };

// level 0 returns the control mesh itself, triangulated (normals from the faces).
[[nodiscard]] SurfaceMeshResult subdivide(const ControlMesh& control, int level,
                                          LimitMethod method = LimitMethod::kMasks);

}  // namespace cathbox::vessel

// subdivide() where OpenSubdiv is not built (the WebAssembly session): the surface comes made
// from elsewhere (vessel/mesh_wire.hpp), and meshing here is an error that says so.
#include "vessel/subdivision.hpp"

namespace cathbox::vessel {

SurfaceMeshResult subdivide(const ControlMesh& /*control*/, int /*level*/, LimitMethod /*method*/,
                            const LevelAdjuster& /*before_last_step*/) {
  return base::Error{"this build has no OpenSubdiv: take the vessel surface from the server's "
                     "/mesh?level=collision or `cathbox vessel mesh -o FILE.cbxmesh`"};
}

}  // namespace cathbox::vessel

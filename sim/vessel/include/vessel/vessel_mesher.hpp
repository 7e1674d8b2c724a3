#pragma once
// The whole pipeline in one call: HCLM file or model -> validated graph -> smoothed centerline
// -> control mesh -> Catmull-Clark limit surface, long junction patches fitted to their branches
// on the way (SurfaceMesh). This is the entry point the
// collision, tool and trainer modules use:
//
//   auto built = cathbox::vessel::load_surface_mesh("cases/neuro.hclm");
//   if (!built.ok()) { report(built.error().message); }  // "cases/neuro.hclm:12: radius ..." etc.
//   const SurfaceMesh& mesh = *built;
#include <string>

#include "base/result.hpp"
#include "vessel/control_mesh.hpp"
#include "vessel/mesh_options.hpp"
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

struct VesselSurface {
  VesselModel smoothed;   // the model after smoothing (the surface follows this centerline)
  ControlMesh control;    // the control mesh before subdivision
  SurfaceMesh mesh;       // the limit surface
  int euler_characteristic = 2;  // expected for the closed surface: 2 * components - 2 * cycles
  std::string error;      // empty on success; one line, starting "file:line:" for file problems
  [[nodiscard]] bool ok() const { return error.empty(); }
};

// The model must be valid (see validate_model); an invalid one yields an error, never a crash.
[[nodiscard]] VesselSurface build_vessel_surface(const VesselModel& model, const MeshOptions& options = {});

// The same with the limit surface made elsewhere (the WebAssembly session, which has no
// OpenSubdiv, takes it from the server: vessel/mesh_wire.hpp): validates and smooths the model,
// and takes `made` as the mesh (the control mesh stays empty). It must be the surface
// build_vessel_surface(model, options) gives, which the caller vouches for.
[[nodiscard]] VesselSurface build_vessel_surface(const VesselModel& model, SurfaceMesh made,
                                                 const MeshOptions& options = {});

// Reads, validates and meshes an HCLM file.
[[nodiscard]] VesselSurface load_vessel_surface(const std::string& hclm_path, const MeshOptions& options = {});

// The mesh, or the one line load_vessel_surface() would give.
using SurfaceMeshLoad = base::Result<SurfaceMesh>;
// Shorthand for load_vessel_surface() keeping only the mesh.
[[nodiscard]] SurfaceMeshLoad load_surface_mesh(const std::string& hclm_path, const MeshOptions& options = {});

}  // namespace cathbox::vessel

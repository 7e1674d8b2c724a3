#pragma once
// A case's own wall (`surface FILE` in the case file): a lumen made elsewhere, e.g. the one
// `cathbox vessel import IN.stl --surface-out lumen.cbxmesh` keeps, as CBXMESH2 bytes
// (vessel/mesh_wire.hpp). Collision, the 3D view and fluoroscopy use it as it is; the case's
// HCLM still gives the centreline graph (route, targets, flow, entry).
#include <string>
#include <string_view>

#include "base/result.hpp"
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

// Files larger than this are refused before reading (a 300 k-triangle lumen is ~9 MB).
inline constexpr std::size_t kMaxCaseSurfaceBytes = 256u << 20;

// The bytes of `path` (at most kMaxCaseSurfaceBytes), or one line "path: what".
[[nodiscard]] base::Result<std::string> read_case_surface_bytes(const std::string& path);

// The surface from its bytes: closed, manifold, one orientation, outward (positive volume). Or
// one line "path: what".
[[nodiscard]] base::Result<vessel::SurfaceMesh> decode_case_surface(std::string_view bytes, const std::string& path);
// Empty when every triangle's region names a segment of the model the surface walls; else one
// line "path: ..." (a surface meant for another vessel).
[[nodiscard]] std::string check_surface_regions(const vessel::SurfaceMesh& mesh, const vessel::VesselModel& model,
                                                const std::string& path);

}  // namespace cathbox::tool

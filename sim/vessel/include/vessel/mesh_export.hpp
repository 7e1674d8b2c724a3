#pragma once
// Writing a SurfaceMesh to common formats: Wavefront OBJ (positions, normals, one group per
// region), binary little-endian PLY (positions, normals, faces with region kind and id) and
// binary STL (facet normals), and the exact CBXMESH2 bytes (vessel/mesh_wire.hpp).
#include <string>

#include "vessel/surface_mesh.hpp"

namespace cathbox::vessel {

// Format from the extension (.obj, .ply, .stl, .cbxmesh, case-insensitive). Empty string on success.
[[nodiscard]] std::string write_mesh(const SurfaceMesh& mesh, const std::string& path);

}  // namespace cathbox::vessel

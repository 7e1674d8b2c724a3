#pragma once
// The vessel surface a WebAssembly session runs on, read from a CBXMESH2 file
// (vessel/mesh_wire.hpp): `cathbox vessel mesh VESSEL -o FILE.cbxmesh` natively, or the
// server's /mesh?level=collision.
#include <string>

#include "base/result.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::wasm {

// The mesh, or one line "FILE: byte N: what".
[[nodiscard]] base::Result<vessel::SurfaceMesh> read_surface_file(const std::string& path);

}  // namespace cathbox::wasm

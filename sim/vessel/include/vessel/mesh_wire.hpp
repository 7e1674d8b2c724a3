#pragma once
// The vessel surface as bytes (`CBXMESH2`): every field a SurfaceMesh holds, float for float, so
// a program that cannot mesh (the WebAssembly session has no OpenSubdiv) builds the same
// collision tree from a mesh made elsewhere (the server's /mesh?level=collision, or
// `cathbox vessel mesh -o FILE.cbxmesh`) and runs the same physics, hash for hash.
//
// Layout, little-endian: "CBXMESH2", u32 vertices V, u32 triangles T, V x 3 f32 positions (mm),
// V x 3 f32 normals, T x 3 u32 vertex indices, T x (u8 region kind, i32 region id).
#include <cstdint>
#include <span>
#include <string>

#include "base/result.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::vessel {

inline constexpr char kMeshWireMagic[] = "CBXMESH2";
// Refuses more than this many vertices or triangles (a hostile header cannot size a huge buffer).
inline constexpr std::uint32_t kMeshWireMaxElements = 1u << 24;

[[nodiscard]] std::string encode_mesh_wire(const SurfaceMesh& mesh);

// The mesh, or one line "byte N: what" (a short buffer, a bad magic, an index beyond the
// vertices, an unknown region kind, trailing bytes).
[[nodiscard]] base::Result<SurfaceMesh> decode_mesh_wire(std::span<const std::uint8_t> bytes);

}  // namespace cathbox::vessel

// Fuzzes decode_mesh_wire() (vessel/mesh_wire.hpp, the surface the WebAssembly session takes
// from the server): any bytes give a mesh or one error line, never a crash; a mesh it accepts
// has every index in range and encodes back to the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>

#include "vessel/mesh_wire.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto decoded = cathbox::vessel::decode_mesh_wire(std::span<const std::uint8_t>(data, size));
  if (!decoded) {
    if (decoded.error().message.empty()) std::abort();
    return 0;
  }
  const cathbox::vessel::SurfaceMesh& mesh = decoded.value();
  for (const std::uint32_t index : mesh.triangles) {
    if (index >= mesh.vertex_count()) std::abort();
  }
  const std::string again = cathbox::vessel::encode_mesh_wire(mesh);
  if (again.size() != size || std::memcmp(again.data(), data, size) != 0) std::abort();
  return 0;
}

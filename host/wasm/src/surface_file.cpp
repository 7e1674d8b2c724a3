#include "wasm/surface_file.hpp"

#include <fstream>
#include <iterator>
#include <vector>

#include "vessel/mesh_wire.hpp"

namespace cathbox::wasm {

base::Result<vessel::SurfaceMesh> read_surface_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return base::Error{path + ": cannot open file"};
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  base::Result<vessel::SurfaceMesh> mesh = vessel::decode_mesh_wire(bytes);
  if (!mesh) return base::Error{path + ": " + mesh.error().message};
  return mesh;
}

}  // namespace cathbox::wasm

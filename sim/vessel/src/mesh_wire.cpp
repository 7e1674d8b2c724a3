#include "vessel/mesh_wire.hpp"

#include <cstring>
#include <utility>

#include "base/bit_cast.hpp"
#include "base/byte_order.hpp"

namespace cathbox::vessel {
namespace {

constexpr std::size_t kMagicBytes = sizeof(kMeshWireMagic) - 1;
constexpr std::size_t kHeaderBytes = kMagicBytes + 8;
constexpr std::size_t kVertexBytes = 24;
constexpr std::size_t kTriangleBytes = 17;

void put_u32(std::string& out, std::uint32_t v) {
  std::uint8_t b[4];
  base::put_le(b, v);
  out.append(reinterpret_cast<const char*>(b), 4);
}

void put_vec(std::string& out, const glm::vec3& v) {
  for (int i = 0; i < 3; ++i) put_u32(out, base::bit_cast<std::uint32_t>(v[i]));
}

glm::vec3 get_vec(const std::uint8_t* p) {
  glm::vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = base::bit_cast<float>(base::get_le<std::uint32_t>(p + 4 * i));
  return v;
}

base::Error at(std::size_t byte, const std::string& what) { return base::Error{"byte " + std::to_string(byte) + ": " + what}; }

}  // namespace

std::string encode_mesh_wire(const SurfaceMesh& mesh) {
  const auto vertices = static_cast<std::uint32_t>(mesh.vertex_count());
  const auto triangles = static_cast<std::uint32_t>(mesh.triangle_count());
  std::string out(kMeshWireMagic, kMagicBytes);
  out.reserve(kHeaderBytes + vertices * kVertexBytes + triangles * kTriangleBytes);
  put_u32(out, vertices);
  put_u32(out, triangles);
  for (const glm::vec3& p : mesh.positions_mm) put_vec(out, p);
  for (std::uint32_t i = 0; i < vertices; ++i) put_vec(out, i < mesh.normals.size() ? mesh.normals[i] : glm::vec3(0.0F));
  for (std::uint32_t index : mesh.triangles) put_u32(out, index);
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const FaceRegion r = t < mesh.triangle_regions.size() ? mesh.triangle_regions[t] : FaceRegion{};
    out.push_back(static_cast<char>(r.kind));
    put_u32(out, static_cast<std::uint32_t>(r.id));
  }
  return out;
}

base::Result<SurfaceMesh> decode_mesh_wire(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kHeaderBytes) return at(bytes.size(), "truncated header (" + std::to_string(bytes.size()) + " bytes)");
  if (std::memcmp(bytes.data(), kMeshWireMagic, kMagicBytes) != 0) return at(0, "not a CBXMESH2 mesh");
  const auto vertices = base::get_le<std::uint32_t>(bytes.data() + kMagicBytes);
  const auto triangles = base::get_le<std::uint32_t>(bytes.data() + kMagicBytes + 4);
  if (vertices > kMeshWireMaxElements) return at(kMagicBytes, std::to_string(vertices) + " vertices, over the limit");
  if (triangles > kMeshWireMaxElements) return at(kMagicBytes + 4, std::to_string(triangles) + " triangles, over the limit");
  const std::size_t want = kHeaderBytes + std::size_t{vertices} * kVertexBytes + std::size_t{triangles} * kTriangleBytes;
  if (bytes.size() < want) return at(bytes.size(), "truncated: " + std::to_string(want) + " bytes expected");
  if (bytes.size() > want) return at(want, std::to_string(bytes.size() - want) + " bytes after the mesh");
  SurfaceMesh mesh;
  mesh.positions_mm.resize(vertices);
  mesh.normals.resize(vertices);
  mesh.triangles.resize(std::size_t{triangles} * 3);
  mesh.triangle_regions.resize(triangles);
  std::size_t pos = kHeaderBytes;
  for (glm::vec3& p : mesh.positions_mm) p = get_vec(bytes.data() + (std::exchange(pos, pos + 12)));
  for (glm::vec3& n : mesh.normals) n = get_vec(bytes.data() + (std::exchange(pos, pos + 12)));
  for (std::uint32_t& index : mesh.triangles) {
    index = base::get_le<std::uint32_t>(bytes.data() + pos);
    if (index >= vertices) return at(pos, "vertex index " + std::to_string(index) + " of " + std::to_string(vertices));
    pos += 4;
  }
  for (FaceRegion& r : mesh.triangle_regions) {
    const std::uint8_t kind = bytes[pos];
    if (kind > static_cast<std::uint8_t>(RegionKind::kCap)) return at(pos, "region kind " + std::to_string(kind));
    r.kind = static_cast<RegionKind>(kind);
    r.id = static_cast<std::int32_t>(base::get_le<std::uint32_t>(bytes.data() + pos + 1));
    pos += 5;
  }
  return mesh;
}

}  // namespace cathbox::vessel

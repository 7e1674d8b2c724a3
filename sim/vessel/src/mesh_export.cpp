#include "vessel/mesh_export.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>

#include <glm/geometric.hpp>

namespace cathbox::vessel {
namespace {

void put_u32(std::ofstream& out, std::uint32_t v) {
  const std::array<char, 4> b = {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
                                 static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
  out.write(b.data(), 4);
}
void put_i32(std::ofstream& out, std::int32_t v) { put_u32(out, static_cast<std::uint32_t>(v)); }
void put_f32(std::ofstream& out, float v) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  put_u32(out, bits);
}
void put_vec(std::ofstream& out, const glm::vec3& v) {
  put_f32(out, v.x);
  put_f32(out, v.y);
  put_f32(out, v.z);
}

const char* kind_name(RegionKind kind) {
  switch (kind) {
    case RegionKind::kSegment: return "segment";
    case RegionKind::kJunction: return "junction";
    case RegionKind::kCap: return "cap";
  }
  return "region";
}

void write_obj(const SurfaceMesh& mesh, std::ofstream& out) {
  out << "# cathbox vessel surface, millimetres\n";
  char buf[128];
  for (const glm::vec3& p : mesh.positions_mm) {
    std::snprintf(buf, sizeof buf, "v %.6g %.6g %.6g\n", static_cast<double>(p.x), static_cast<double>(p.y),
                  static_cast<double>(p.z));
    out << buf;
  }
  for (const glm::vec3& n : mesh.normals) {
    std::snprintf(buf, sizeof buf, "vn %.5f %.5f %.5f\n", static_cast<double>(n.x), static_cast<double>(n.y),
                  static_cast<double>(n.z));
    out << buf;
  }
  FaceRegion current{RegionKind::kSegment, -1};
  bool first = true;
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const FaceRegion r = mesh.triangle_regions.at(f);
    if (first || !(r == current)) {
      out << "g " << kind_name(r.kind) << "_" << r.id << "\n";
      current = r;
      first = false;
    }
    const std::uint32_t a = mesh.triangles[3 * f] + 1;
    const std::uint32_t b = mesh.triangles[3 * f + 1] + 1;
    const std::uint32_t c = mesh.triangles[3 * f + 2] + 1;
    std::snprintf(buf, sizeof buf, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c);
    out << buf;
  }
}

void write_ply(const SurfaceMesh& mesh, std::ofstream& out) {
  out << "ply\nformat binary_little_endian 1.0\ncomment cathbox vessel surface, millimetres\n"
      << "element vertex " << mesh.vertex_count() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property float nx\nproperty float ny\nproperty float nz\n"
      << "element face " << mesh.triangle_count() << "\n"
      << "property list uchar uint vertex_indices\nproperty uchar region_kind\nproperty int region_id\n"
      << "end_header\n";
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    put_vec(out, mesh.positions_mm[i]);
    put_vec(out, mesh.normals[i]);
  }
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    out.put(3);
    for (int k = 0; k < 3; ++k) put_u32(out, mesh.triangles[3 * f + static_cast<std::size_t>(k)]);
    out.put(static_cast<char>(mesh.triangle_regions.at(f).kind));
    put_i32(out, mesh.triangle_regions.at(f).id);
  }
}

void write_stl(const SurfaceMesh& mesh, std::ofstream& out) {
  std::array<char, 80> header{};
  const char* text = "cathbox vessel surface (mm)";
  std::memcpy(header.data(), text, std::strlen(text));
  out.write(header.data(), header.size());
  put_u32(out, static_cast<std::uint32_t>(mesh.triangle_count()));
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const glm::vec3& a = mesh.positions_mm[mesh.triangles[3 * f]];
    const glm::vec3& b = mesh.positions_mm[mesh.triangles[3 * f + 1]];
    const glm::vec3& c = mesh.positions_mm[mesh.triangles[3 * f + 2]];
    glm::vec3 n = glm::cross(b - a, c - a);
    const float len = glm::length(n);
    n = len > 0.0f ? n / len : glm::vec3(0.0f);
    put_vec(out, n);
    put_vec(out, a);
    put_vec(out, b);
    put_vec(out, c);
    out.put(0);
    out.put(0);
  }
}

}  // namespace

std::string write_mesh(const SurfaceMesh& mesh, const std::string& path) {
  std::string ext = path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".obj" && ext != ".ply" && ext != ".stl") return "unknown mesh format '" + ext + "' (use .obj, .ply or .stl)";
  std::ofstream out(path, std::ios::binary);
  if (!out) return "cannot open " + path + " for writing";
  if (ext == ".obj") write_obj(mesh, out);
  else if (ext == ".ply") write_ply(mesh, out);
  else write_stl(mesh, out);
  out.flush();
  if (!out) return "cannot write " + path;
  return {};
}

}  // namespace cathbox::vessel

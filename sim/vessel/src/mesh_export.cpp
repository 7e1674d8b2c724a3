#include "vessel/mesh_export.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "vessel/mesh_wire.hpp"

namespace cathbox::vessel {
namespace {

// Bytes appended to a buffer that goes to the file whenever it holds kChunk bytes: one write()
// per megabyte instead of one stream call per number.
class FileWriter {
 public:
  static constexpr std::size_t kChunk = 1 << 20;

  explicit FileWriter(const std::string& path)
      : file_(std::fopen(path.c_str(), "wb")), buffer_(std::make_unique_for_overwrite<char[]>(kChunk)) {}
  ~FileWriter() {
    if (file_) std::fclose(file_);
  }
  FileWriter(const FileWriter&) = delete;
  FileWriter& operator=(const FileWriter&) = delete;

  [[nodiscard]] bool open() const { return file_ != nullptr; }

  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const char*>(data);
    while (n > 0) {
      if (used_ == kChunk) flush();
      const std::size_t take = std::min(n, kChunk - used_);
      std::memcpy(buffer_.get() + used_, p, take);
      used_ += take;
      p += take;
      n -= take;
    }
  }
  // Room for n <= kChunk bytes at the end of the buffer (flushing it first if needed), filled by
  // the caller: a fixed-size record copied there compiles to a few moves, not a memcpy call.
  [[nodiscard]] char* record(std::size_t n) {
    if (used_ + n > kChunk) flush();
    char* at = buffer_.get() + used_;
    used_ += n;
    return at;
  }
  void text(std::string_view s) { bytes(s.data(), s.size()); }
  void put(char c) {
    if (used_ == kChunk) flush();
    buffer_[used_++] = c;
  }
  void u32(std::uint32_t v) { bytes(&v, 4); }  // little-endian hosts only (asserted below)
  // A number as printf's %.<precision>g or %.<precision>f would print it.
  void number(double v, std::chars_format format, int precision) {
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, format, precision);
    if (ec == std::errc()) bytes(buf, static_cast<std::size_t>(end - buf));
  }
  void integer(std::uint64_t v) {
    char buf[24];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    if (ec == std::errc()) bytes(buf, static_cast<std::size_t>(end - buf));
  }

  // Writes what is left and closes; the error, or empty.
  [[nodiscard]] std::string finish(const std::string& path) {
    flush();
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    return failed_ || !closed ? "cannot write " + path : std::string();
  }

 private:
  void flush() {
    if (used_ > 0 && std::fwrite(buffer_.get(), 1, used_, file_) != used_) failed_ = true;
    used_ = 0;
  }

  std::FILE* file_;
  std::unique_ptr<char[]> buffer_;
  std::size_t used_ = 0;
  bool failed_ = false;
};

// Little-endian on the wire whatever the host: the layouts below assume it (checked at compile
// time so a big-endian port has to add the swaps).
static_assert(std::endian::native == std::endian::little);
// glm vectors are three packed floats, written as they are in memory.
static_assert(sizeof(glm::vec3) == 12);

const char* kind_name(RegionKind kind) {
  switch (kind) {
    case RegionKind::kSegment: return "segment";
    case RegionKind::kJunction: return "junction";
    case RegionKind::kCap: return "cap";
  }
  return "region";
}

void write_obj(const SurfaceMesh& mesh, FileWriter& out) {
  out.text("# cathbox vessel surface, millimetres\n");
  const auto lines = [&out](const char* label, const std::vector<glm::vec3>& values, std::chars_format format,
                           int precision) {
    for (const glm::vec3& v : values) {
      out.text(label);
      for (int k = 0; k < 3; ++k) {
        out.put(' ');
        out.number(v[k], format, precision);
      }
      out.put('\n');
    }
  };
  lines("v", mesh.positions_mm, std::chars_format::general, 6);  // as %.6g
  lines("vn", mesh.normals, std::chars_format::fixed, 5);        // as %.5f
  FaceRegion current{RegionKind::kSegment, -1};
  bool first = true;
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const FaceRegion r = mesh.triangle_regions.at(f);
    if (first || !(r == current)) {
      out.text("g ");
      out.text(kind_name(r.kind));
      out.put('_');
      if (r.id < 0) out.put('-');
      out.integer(static_cast<std::uint64_t>(r.id < 0 ? -static_cast<std::int64_t>(r.id) : r.id));
      out.put('\n');
      current = r;
      first = false;
    }
    out.put('f');
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint64_t v = std::uint64_t{mesh.triangles[3 * f + k]} + 1;
      out.put(' ');
      out.integer(v);
      out.text("//");
      out.integer(v);
    }
    out.put('\n');
  }
}

void write_ply(const SurfaceMesh& mesh, FileWriter& out) {
  out.text("ply\nformat binary_little_endian 1.0\ncomment cathbox vessel surface, millimetres\nelement vertex ");
  out.integer(mesh.vertex_count());
  out.text("\nproperty float x\nproperty float y\nproperty float z\n"
           "property float nx\nproperty float ny\nproperty float nz\nelement face ");
  out.integer(mesh.triangle_count());
  out.text("\nproperty list uchar uint vertex_indices\nproperty uchar region_kind\nproperty int region_id\n"
           "end_header\n");
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    char* vertex = out.record(24);
    std::memcpy(vertex, &mesh.positions_mm[i], 12);
    std::memcpy(vertex + 12, &mesh.normals[i], 12);
  }
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const FaceRegion region = mesh.triangle_regions.at(f);
    char* face = out.record(18);  // 1 + 3 * 4 + 1 + 4 bytes
    face[0] = 3;
    std::memcpy(face + 1, &mesh.triangles[3 * f], 12);
    face[13] = static_cast<char>(region.kind);
    std::memcpy(face + 14, &region.id, 4);
  }
}

void write_stl(const SurfaceMesh& mesh, FileWriter& out) {
  std::array<char, 80> header{};
  const char* text = "cathbox vessel surface (mm)";
  std::memcpy(header.data(), text, std::strlen(text));
  out.bytes(header.data(), header.size());
  out.u32(static_cast<std::uint32_t>(mesh.triangle_count()));
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const glm::vec3& a = mesh.positions_mm[mesh.triangles[3 * f]];
    const glm::vec3& b = mesh.positions_mm[mesh.triangles[3 * f + 1]];
    const glm::vec3& c = mesh.positions_mm[mesh.triangles[3 * f + 2]];
    glm::vec3 n = glm::cross(b - a, c - a);
    const float len = glm::length(n);
    n = len > 0.0f ? n / len : glm::vec3(0.0f);
    std::array<glm::vec3, 4> facet = {n, a, b, c};
    static_assert(sizeof(facet) == 48);
    out.bytes(facet.data(), sizeof facet);
    out.put(0);
    out.put(0);
  }
}

}  // namespace

std::string write_mesh(const SurfaceMesh& mesh, const std::string& path) {
  std::string ext = path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".obj" && ext != ".ply" && ext != ".stl" && ext != ".cbxmesh") {
    return "unknown mesh format '" + ext + "' (use .obj, .ply, .stl or .cbxmesh)";
  }
  FileWriter out(path);
  if (!out.open()) return "cannot open " + path + " for writing";
  if (ext == ".obj") write_obj(mesh, out);
  else if (ext == ".ply") write_ply(mesh, out);
  else if (ext == ".cbxmesh") out.text(encode_mesh_wire(mesh));
  else write_stl(mesh, out);
  return out.finish(path);
}

}  // namespace cathbox::vessel

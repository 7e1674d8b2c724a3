#include "server/case_library.hpp"

#include <bit>
#include <filesystem>
#include <sstream>

#include "server/json_input.hpp"
#include "server/sha256.hpp"
#include "server/zstd_codec.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_surface.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_wire.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::server {

namespace {

// The 1-based line of the first statement starting with `keyword`, or 0.
int line_of(const std::string& text, const std::string& keyword) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::istringstream words(line);
    std::string first;
    if (words >> first && first == keyword) return n;
  }
  return 0;
}

Error refuse(const std::string& file, int line, const std::string& message) {
  return make_error(422, file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + message);
}

// A `surface FILE` case: the uploaded surface is that file (plain name) and a valid CBXMESH2
// lumen; a case without the line carries no surface.
Status check_surface(const CaseBundle& b, const tool::Case& c) {
  const int line = line_of(b.case_text, "surface");
  if (c.surface_path.empty()) {
    if (!b.surface_file.empty() || !b.surface_bytes.empty()) return refuse(b.case_file, 0, "the case has no 'surface' line, but a surface was uploaded");
    return Ok{};
  }
  const std::string name = std::filesystem::path(c.surface_path).filename().string();
  if (b.surface_file.empty()) return refuse(b.case_file, line, "the case names surface '" + name + "': upload it as surface_file/surface_hex");
  if (c.surface_path != name || name != b.surface_file) {
    return refuse(b.case_file, line, "surface '" + c.surface_path + "' is not the uploaded surface file '" + b.surface_file + "' (give its plain name)");
  }
  if (const std::string bad = check_slug(b.surface_file); !bad.empty()) return make_error(400, "field 'surface_file': " + bad);
  base::Result<vessel::SurfaceMesh> decoded = tool::decode_case_surface(b.surface_bytes, b.surface_file);
  if (!decoded) return make_error(422, decoded.error().message);
  return Ok{};
}

}  // namespace

Result<CaseCheck> check_case(const CaseBundle& b, const UploadLimits& limits) {
  if (const std::string bad = check_slug(b.case_file); !bad.empty()) return make_error(400, "field 'case_file': " + bad);
  if (!b.hclm_file.empty()) {
    if (const std::string bad = check_slug(b.hclm_file); !bad.empty()) return make_error(400, "field 'hclm_file': " + bad);
  }
  if (b.case_text.size() > kMaxCaseTextBytes) return make_error(413, b.case_file + ": larger than " + std::to_string(kMaxCaseTextBytes) + " bytes");
  if (b.hclm_text.size() > kMaxHclmBytes) return make_error(413, b.hclm_file + ": larger than " + std::to_string(kMaxHclmBytes) + " bytes");

  const tool::CaseParse parsed = tool::parse_case(b.case_text, b.case_file);
  if (!parsed) return make_error(422, parsed.error().message);
  const tool::Case& c = *parsed;
  if (Status s = check_surface(b, c); !s) return s.error();
  CaseCheck out;
  out.bundle = b;
  out.title = c.name;
  if (c.vessel_path.empty()) {
    if (!b.hclm_file.empty() || !b.hclm_text.empty()) {
      return refuse(b.case_file, 0, "the case is made of 'tube' lines and names no vessel, but an HCLM file was uploaded");
    }
    return out;
  }
  const std::string vessel_name = std::filesystem::path(c.vessel_path).filename().string();
  const int vessel_line = line_of(b.case_text, "vessel");
  if (b.hclm_file.empty()) {
    return refuse(b.case_file, vessel_line, "the case names vessel '" + vessel_name + "': upload it as hclm_file/hclm");
  }
  if (c.vessel_path != vessel_name || vessel_name != b.hclm_file) {
    return refuse(b.case_file, vessel_line,
                  "vessel '" + c.vessel_path + "' is not the uploaded HCLM file '" + b.hclm_file + "' (give its plain name)");
  }
  const vessel::HclmReadResult model = vessel::read_hclm(b.hclm_text, b.hclm_file);
  if (!model.ok()) {
    std::string message = model.errors.front().to_string();
    if (model.errors.size() > 1) message += " (and " + std::to_string(model.errors.size() - 1) + " more)";
    return make_error(422, message);
  }
  if (c.target) {
    bool found = false;
    for (const vessel::Segment& s : model.model.segments) found = found || s.id == c.target->segment;
    if (!found) {
      return refuse(b.case_file, line_of(b.case_text, "target"),
                    "target segment " + std::to_string(c.target->segment) + " is not a segment of " + b.hclm_file);
    }
  }
  // Before meshing: a few MB of HCLM can ask for tens of GB of surface.
  if (Status s = check_vessel_bounds(b.hclm_text, b.hclm_file, limits); !s) return s.error();
  vessel::MeshOptions level2;
  level2.subdivision_level = 2;
  const vessel::VesselSurface surface = vessel::build_vessel_surface(model.model, level2);
  if (!surface.ok()) {
    const std::string& e = surface.error;
    return make_error(422, e.rfind(b.hclm_file, 0) == 0 ? e : b.hclm_file + ": " + e);
  }
  out.mesh_vertices = static_cast<std::int64_t>(surface.mesh.vertex_count());
  out.mesh_triangles = static_cast<std::int64_t>(surface.mesh.triangle_count());
  out.mesh_bytes = out.mesh_vertices * 24 + out.mesh_triangles * 12;
  return out;
}

namespace {

Result<vessel::VesselSurface> mesh_bundle(const CaseBundle& b, const vessel::MeshOptions& options) {
  if (b.hclm_text.empty()) return make_error(404, b.case_file + ": the case names no vessel (made of 'tube' lines): no mesh");
  const vessel::HclmReadResult model = vessel::read_hclm(b.hclm_text, b.hclm_file);
  if (!model.ok()) return make_error(422, model.errors.front().to_string());
  vessel::VesselSurface surface = vessel::build_vessel_surface(model.model, options);
  if (!surface.ok()) return make_error(422, surface.error);
  return surface;
}

}  // namespace

Result<std::string> collision_mesh(const CaseBundle& b) {
  Result<vessel::VesselSurface> surface = mesh_bundle(b, vessel::MeshOptions{});
  if (!surface) return surface.error();
  return vessel::encode_mesh_wire(surface.value().mesh);
}

Result<std::string> browser_mesh(const CaseBundle& b) {
  vessel::MeshOptions coarse;
  coarse.subdivision_level = kBrowserMeshLevel;
  coarse.ring_points = kBrowserMeshRingPoints;
  Result<vessel::VesselSurface> surface = mesh_bundle(b, coarse);
  if (!surface) return surface.error();
  const vessel::SurfaceMesh& m = surface.value().mesh;
  static_assert(sizeof(glm::vec3) == 12 && std::endian::native == std::endian::little);
  const auto vertices = static_cast<std::uint32_t>(m.vertex_count());
  const auto triangles = static_cast<std::uint32_t>(m.triangle_count());
  std::string out = "CBXMESH1";
  const auto put = [&out](const void* data, std::size_t n) { out.append(static_cast<const char*>(data), n); };
  out.reserve(16 + std::size_t{vertices} * 24 + std::size_t{triangles} * 12);
  put(&vertices, 4);
  put(&triangles, 4);
  put(m.positions_mm.data(), m.positions_mm.size() * 12);
  put(m.normals.data(), m.normals.size() * 12);
  put(m.triangles.data(), m.triangles.size() * 4);
  return out;
}

Result<CaseUploadOutcome> CaseLibrary::upload(const std::string& name, const CaseBundle& bundle, std::optional<std::int64_t> uploader_id,
                                              std::int64_t now_us) {
  if (const std::string bad = check_slug(name); !bad.empty()) return make_error(400, "field 'name': " + bad);
  Result<CaseCheck> checked = check_case(bundle);
  if (!checked) return checked.error();
  const CaseCheck& c = checked.value();
  const std::string json = bundle_json(bundle);
  const std::string wire = zstd_compress(json, zstd_level_);
  CaseVersion meta;
  meta.title = c.title;
  meta.case_file = bundle.case_file;
  meta.hclm_file = bundle.hclm_file;
  meta.content_hash = sha256_hex(json);
  meta.raw_bytes = static_cast<std::int64_t>(bundle.case_text.size() + bundle.hclm_text.size());
  meta.wire_bytes = static_cast<std::int64_t>(wire.size());
  meta.mesh_vertices = c.mesh_vertices;
  meta.mesh_triangles = c.mesh_triangles;
  meta.mesh_bytes = c.mesh_bytes;
  meta.uploaded_by = uploader_id;
  const CaseInsert inserted = store_.insert_case_version(name, meta, wire, now_us);
  return CaseUploadOutcome{inserted.version, inserted.created};
}

}  // namespace cathbox::server

#include "scenario/case_surface.hpp"

#include <filesystem>
#include <span>

#include "base/read_file.hpp"

#include "vessel/mesh_analysis.hpp"
#include "vessel/mesh_wire.hpp"

namespace cathbox::tool {

base::Result<std::string> read_case_surface_bytes(const std::string& path) {
  base::Result<std::string, base::ReadFileError> bytes = base::read_file(path, kMaxCaseSurfaceBytes);
  if (bytes) return std::move(*bytes);
  if (bytes.error().kind == base::ReadFileError::Kind::kCannotOpen) return base::Error{path + ": cannot open the case's surface"};
  return base::Error{path + ": surface of " + std::to_string(bytes.error().size_bytes) + " bytes is too large (at most " +
                     std::to_string(kMaxCaseSurfaceBytes) + ")"};
}

base::Result<vessel::SurfaceMesh> decode_case_surface(std::string_view bytes, const std::string& path) {
  const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
  base::Result<vessel::SurfaceMesh> mesh = vessel::decode_mesh_wire(std::span<const std::uint8_t>(data, bytes.size()));
  if (!mesh) {
    std::string hint;
    if (std::filesystem::path(path).extension() != ".cbxmesh") {
      hint = " (a case's surface is CBXMESH2: `cathbox vessel import IN --surface-out FILE.cbxmesh`)";
    }
    return base::Error{path + ": " + mesh.error().message + hint};
  }
  if (mesh->triangle_count() == 0) return base::Error{path + ": the surface has no triangles"};
  const vessel::MeshAnalysis a = vessel::analyze_mesh(*mesh);
  if (!a.closed()) return base::Error{path + ": the surface is not closed (" + std::to_string(a.boundary_edges) + " boundary edges)"};
  if (!a.manifold()) return base::Error{path + ": the surface is not manifold"};
  if (!a.consistently_oriented() || !(a.signed_volume_mm3 > 0.0)) {
    return base::Error{path + ": the surface is not oriented outward throughout"};
  }
  return mesh;
}

std::string check_surface_regions(const vessel::SurfaceMesh& mesh, const vessel::VesselModel& model, const std::string& path) {
  for (std::size_t t = 0; t < mesh.triangle_regions.size(); ++t) {
    const vessel::FaceRegion& r = mesh.triangle_regions[t];
    if (r.kind != vessel::RegionKind::kJunction && !model.index_of(r.id)) {
      return path + ": triangle " + std::to_string(t) + " belongs to segment " + std::to_string(r.id) +
             ", which the case's vessel does not have (a surface of another vessel?)";
    }
  }
  return {};
}

}  // namespace cathbox::tool

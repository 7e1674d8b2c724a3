#include "app/fluoro_vessel.hpp"

#include <algorithm>
#include <utility>

#include "vessel/vessel_mesher.hpp"

namespace cathbox::app {
namespace {

// The two cells whose centres bracket an arc position, and the weight of the second.
VertexCells bracket(std::span<const double> bounds, std::uint32_t first_cell, double arc_mm) {
  const std::size_t n = bounds.size() - 1;
  VertexCells v{first_cell, first_cell, 0.0F};
  const auto centre = [&](std::size_t i) { return 0.5 * (bounds[i] + bounds[i + 1]); };
  if (n < 2 || arc_mm <= centre(0)) return v;
  if (arc_mm >= centre(n - 1)) {
    v.a = v.b = first_cell + static_cast<std::uint32_t>(n - 1);
    return v;
  }
  // The cell holding the position, then the neighbour on the side of its centre.
  const auto it = std::upper_bound(bounds.begin() + 1, bounds.end() - 1, arc_mm);
  std::size_t i = static_cast<std::size_t>(it - bounds.begin()) - 1;
  if (arc_mm < centre(i)) --i;
  v.a = first_cell + static_cast<std::uint32_t>(i);
  v.b = v.a + 1;
  v.w = static_cast<float>((arc_mm - centre(i)) / (centre(i + 1) - centre(i)));
  return v;
}

}  // namespace

FluoroVessel FluoroVessel::build(const vessel::SurfaceMesh& mesh, const flow::ContrastTransport& transport) {
  const vessel::VesselModel& model = transport.network().model();
  FluoroVessel out;
  out.positions_mm = mesh.positions_mm;
  out.triangles = mesh.triangles;
  out.cell_count = transport.cell_count();
  // Each segment's first cell in the flat order.
  std::vector<std::uint32_t> first_cell(model.segments.size(), 0);
  const double* base = transport.cell_concentrations(0).data();
  for (std::uint32_t s = 0; s < model.segments.size(); ++s) {
    first_cell[s] = static_cast<std::uint32_t>(transport.cell_concentrations(s).data() - base);
  }
  // The segment index of each vertex (-1: a junction's, or none yet).
  std::vector<std::int64_t> segment_of(mesh.positions_mm.size(), -1);
  for (std::size_t t = 0; t < mesh.triangle_count() && t < mesh.triangle_regions.size(); ++t) {
    const vessel::FaceRegion& r = mesh.triangle_regions[t];
    if (r.kind == vessel::RegionKind::kJunction) continue;
    const std::optional<std::size_t> s = model.index_of(r.id);
    if (!s) continue;
    for (int k = 0; k < 3; ++k) segment_of[mesh.triangles[3 * t + static_cast<std::size_t>(k)]] = static_cast<std::int64_t>(*s);
  }
  out.cells.resize(mesh.positions_mm.size());
  for (std::size_t v = 0; v < mesh.positions_mm.size(); ++v) {
    const glm::dvec3 p = mesh.positions_mm[v];
    const flow::CenterlinePosition at = segment_of[v] >= 0
                                            ? transport.locator().nearest_on(static_cast<std::uint32_t>(segment_of[v]), p)
                                            : transport.locate(p);
    out.cells[v] = bracket(transport.cell_bounds_mm(at.segment), first_cell[at.segment], at.arc_mm);
  }
  return out;
}

float FluoroVessel::concentration(std::size_t vertex, std::span<const float> cell_mgI_ml) const {
  const VertexCells& c = cells[vertex];
  if (c.a >= cell_mgI_ml.size() || c.b >= cell_mgI_ml.size()) return 0.0F;
  return (1.0F - c.w) * cell_mgI_ml[c.a] + c.w * cell_mgI_ml[c.b];
}

std::vector<float> cell_iodine(const flow::ContrastTransport& transport) {
  std::vector<float> out;
  out.reserve(transport.cell_count());
  for (std::uint32_t s = 0; s < transport.network().model().segments.size(); ++s) {
    for (const double c : transport.cell_concentrations(s)) out.push_back(static_cast<float>(c));
  }
  return out;
}

vessel::MeshOptions fluoro_surface_options(vessel::MeshOptions collision) {
  collision.subdivision_level = std::max(0, collision.subdivision_level - 1);
  return collision;
}

vessel::SurfaceMesh fluoro_surface(const vessel::VesselModel& model) {
  vessel::VesselSurface s = vessel::build_vessel_surface(model, fluoro_surface_options());
  return s.ok() ? std::move(s.mesh) : vessel::SurfaceMesh{};
}

}  // namespace cathbox::app

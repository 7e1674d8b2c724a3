#pragma once
// The vessel surface prepared for the fluoroscopic view: every vertex tied to the contrast
// cells it takes its iodine from (sim/flow ContrastTransport), so a renderer can colour the
// lumen with a pulse's per-cell concentrations without touching the mesh. No GL.
//
// A vertex belongs to the segment of its triangles' region (segment or end cap; a junction's
// vertices take the nearest centreline over all segments); its arc position is the nearest
// point of that segment's centreline; its concentration is linear between the two nearest
// cell centres, as ContrastTransport::concentration() reads the centreline.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "flow/contrast_transport.hpp"
#include "vessel/mesh_options.hpp"
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::app {

struct VertexCells {
  std::uint32_t a = 0;  // cells in the transport's cell order (the flat cell index)
  std::uint32_t b = 0;
  float w = 0.0F;       // concentration = (1 - w) c[a] + w c[b]
};

struct FluoroVessel {
  std::span<const glm::vec3> positions_mm;
  std::span<const std::uint32_t> triangles;  // counter-clockwise seen from outside, closed
  std::vector<VertexCells> cells;            // one per vertex
  std::size_t cell_count = 0;                // the transport's cells

  // `mesh` must be the closed surface of `transport.network().model()` (the same segments)
  // and outlive the result.
  [[nodiscard]] static FluoroVessel build(const vessel::SurfaceMesh& mesh, const flow::ContrastTransport& transport);
  // The concentration at a vertex for per-cell concentrations (as a renderer interpolates them).
  [[nodiscard]] float concentration(std::size_t vertex, std::span<const float> cell_mgI_ml) const;
};

// The surface the fluoroscopic view accumulates iodine on: one Catmull-Clark level below the
// collision surface's (level 1 of 8-point rings: 16 points round a lumen, a quarter of the
// triangles; llvmpipe shades vertices on the render thread, so this is what a contrast frame's
// vertex work scales with). An inscribed 16-gon departs from the circle by 1 - cos(pi/16) = 1.9 %
// of the radius, 0.05 mm for a 2.5 mm internal carotid: a third of a detector pixel at the
// isocentre (220 mm / 1024 / 1.33 = 0.16 mm), below the focal-spot penumbra (0.6 mm spot x
// (M - 1) = 0.2 mm) that blurs every edge of the image anyway.
[[nodiscard]] vessel::MeshOptions fluoro_surface_options(vessel::MeshOptions collision = {});
// The model's surface at fluoro_surface_options(); empty when it cannot be built (the caller
// then draws the iodine on the collision surface).
[[nodiscard]] vessel::SurfaceMesh fluoro_surface(const vessel::VesselModel& model);

// The transport's cell concentrations now, in its flat cell order, as FluoroScene wants them.
[[nodiscard]] std::vector<float> cell_iodine(const flow::ContrastTransport& transport);

}  // namespace cathbox::app

#include "app/vessel_follower.hpp"

#include <chrono>
#include <cmath>
#include <vector>
#include <utility>

#include "vessel/mesh_options.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::app {

vessel::SurfaceMesh overview_mesh(const vessel::VesselModel& model, std::size_t detail_triangles) {
  const vessel::MeshOptions options;
  if (detail_triangles <= kOverviewTriangles || options.subdivision_level <= 0) return {};
  vessel::MeshOptions coarse = options;
  coarse.subdivision_level = options.subdivision_level - 1;
  coarse.ring_points = 4;
  vessel::VesselSurface o = vessel::build_vessel_surface(model, coarse);
  return o.ok() ? std::move(o.mesh) : vessel::SurfaceMesh{};
}

std::shared_ptr<const tool::WallSurface> distended_surface(const tool::WallSurface& surface,
                                                           const tool::WallDistension& distension, double pressure_kPa) {
  std::vector<double> by_index(distension.segment_count());
  const double junction_mm = distension.displacements_mm(pressure_kPa, by_index);
  const auto moved_by = [&](const vessel::FaceRegion& r) {
    if (r.kind == vessel::RegionKind::kJunction) return junction_mm;
    for (std::size_t i = 0; i < distension.segment_count(); ++i) {
      if (distension.segment_id(i) == r.id) return by_index[i];
    }
    return junction_mm;
  };
  auto out = std::make_shared<tool::WallSurface>(surface);
  vessel::SurfaceMesh& mesh = out->mesh;
  std::vector<std::uint8_t> done(mesh.positions_mm.size(), 0);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const double w = t < mesh.triangle_regions.size() ? moved_by(mesh.triangle_regions[t]) : junction_mm;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[3 * t + k];
      if (done[v] != 0) continue;
      done[v] = 1;
      mesh.positions_mm[v] += mesh.normals[v] * static_cast<float>(w);
    }
  }
  return out;
}

VesselFollower::Prepared VesselFollower::prepare(std::uint64_t generation, std::shared_ptr<const tool::WallSurface> surface,
                                                 const flow::ContrastTransport* transport, bool as_is) {
  Prepared p;
  p.generation = generation;
  p.surface = std::move(surface);
  if (!p.surface) return p;
  const vessel::SurfaceMesh& mesh = p.surface->mesh;
  if (!as_is) p.overview = overview_mesh(p.surface->model, mesh.triangle_count());
  p.scene.detail = {mesh.positions_mm, mesh.normals, mesh.triangles};
  p.scene.detail_chunks = SceneRenderer::chunk(p.scene.detail);
  if (!p.overview.triangles.empty()) {
    p.scene.overview = {p.overview.positions_mm, p.overview.normals, p.overview.triangles};
    p.scene.overview_chunks = SceneRenderer::chunk(p.scene.overview);
  }
  if (transport != nullptr) {
    // The fluoroscopic view draws iodine on the surface one level coarser, as at case load; on a
    // surface drawn as it is, on that surface.
    if (!as_is) p.fluoro_mesh = fluoro_surface(p.surface->model);
    p.fluoro_vessel = FluoroVessel::build(p.fluoro_mesh.triangle_count() > 0 ? p.fluoro_mesh : mesh, *transport);
    p.fluoro = FluoroRenderer::prepare_vessel(*p.fluoro_vessel);
  }
  return p;
}

void VesselFollower::reset() {
  if (job_.valid()) job_.wait();
  job_ = {};
  shown_ = 0;
  asked_ = 0;
  shown_step_ = 0;
  asked_step_ = 0;
}

std::optional<VesselFollower::Prepared> VesselFollower::poll(std::uint64_t snapshot_generation, double wall_pressure_kPa,
                                                             const session::Session& session,
                                                             const flow::ContrastTransport* transport, bool wait) {
  const tool::CaseWallField* field = session.wall_field();
  const long step = field != nullptr ? std::lround(wall_pressure_kPa / kDrawnPressureStep_kPa) : 0;
  if (!job_.valid() && (snapshot_generation > shown_ || step != shown_step_)) {
    // A widened lumen (a balloon's swap), else the compliant wall's own surface moved by the pulse.
    std::shared_ptr<const tool::WallSurface> surface =
        snapshot_generation > 0 ? session.wall_surface() : field != nullptr ? field->wall().surface() : nullptr;
    if (!surface) return std::nullopt;
    asked_ = snapshot_generation;
    asked_step_ = step;
    const bool as_is = session.scene().surface_given() || step != 0;
    const tool::WallDistension* distension = field != nullptr && step != 0 ? &field->distension() : nullptr;
    const double pressure_kPa = static_cast<double>(step) * kDrawnPressureStep_kPa;
    job_ = std::async(std::launch::async, [generation = asked_, surface = std::move(surface), transport, as_is, distension,
                                           pressure_kPa] {
      std::shared_ptr<const tool::WallSurface> drawn =
          distension != nullptr ? distended_surface(*surface, *distension, pressure_kPa) : surface;
      return std::make_unique<Prepared>(prepare(generation, std::move(drawn), transport, as_is));
    });
  }
  if (!job_.valid()) return std::nullopt;
  if (!wait && job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
  std::unique_ptr<Prepared> done = job_.get();
  shown_ = asked_;
  shown_step_ = asked_step_;
  return std::move(*done);
}

}  // namespace cathbox::app

#include "app/vessel_follower.hpp"

#include <chrono>
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

VesselFollower::Prepared VesselFollower::prepare(std::uint64_t generation, std::shared_ptr<const tool::WallSurface> surface,
                                                 const flow::ContrastTransport* transport) {
  Prepared p;
  p.generation = generation;
  p.surface = std::move(surface);
  if (!p.surface) return p;
  const vessel::SurfaceMesh& mesh = p.surface->mesh;
  p.overview = overview_mesh(p.surface->model, mesh.triangle_count());
  p.scene.detail = {mesh.positions_mm, mesh.normals, mesh.triangles};
  p.scene.detail_chunks = SceneRenderer::chunk(p.scene.detail);
  if (!p.overview.triangles.empty()) {
    p.scene.overview = {p.overview.positions_mm, p.overview.normals, p.overview.triangles};
    p.scene.overview_chunks = SceneRenderer::chunk(p.scene.overview);
  }
  if (transport != nullptr) {
    // The fluoroscopic view draws iodine on the surface one level coarser, as at case load.
    p.fluoro_mesh = fluoro_surface(p.surface->model);
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
}

std::optional<VesselFollower::Prepared> VesselFollower::poll(std::uint64_t snapshot_generation, const session::Session& session,
                                                             const flow::ContrastTransport* transport, bool wait) {
  if (!job_.valid() && snapshot_generation > shown_) {
    std::shared_ptr<const tool::WallSurface> surface = session.wall_surface();
    if (!surface) return std::nullopt;
    asked_ = snapshot_generation;
    job_ = std::async(std::launch::async, [generation = asked_, surface = std::move(surface), transport] {
      return std::make_unique<Prepared>(prepare(generation, surface, transport));
    });
  }
  if (!job_.valid()) return std::nullopt;
  if (!wait && job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
  std::unique_ptr<Prepared> done = job_.get();
  shown_ = asked_;
  return std::move(*done);
}

}  // namespace cathbox::app

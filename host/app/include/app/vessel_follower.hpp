#pragma once
// The vessel the views draw follows the simulation's wall. When a balloon has widened the lumen,
// the session swaps a new wall in (SceneSnapshot::wall_generation moves on, Session::wall_surface()
// has the widened model and its mesh); the follower then prepares that surface for the renderers
// on a worker thread while the frames go on drawing the old one: the 3D view's chunks, the global
// view's coarser overview meshed from the widened model, and the fluoroscopic view's contrast-cell
// ties and buffers. The render thread only uploads what is ready (one call per renderer), so no
// frame waits for the meshing, and the haptic thread never sees any of it.
//
//   VesselFollower follower;                    // follower.reset() after each scene load
//   each frame: if (auto next = follower.poll(snap.wall_generation, session, transport)) {
//     scene_renderer.upload_vessel(next->scene);  fluoro_renderer.upload_vessel(std::move(*next->fluoro));
//   }
#include <cstdint>
#include <future>
#include <memory>
#include <optional>

#include "app/fluoro_renderer.hpp"
#include "app/fluoro_vessel.hpp"
#include "app/scene_renderer.hpp"
#include "flow/contrast_transport.hpp"
#include "session/session.hpp"
#include "tool/wall_model.hpp"
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::app {

// Above this many triangles the global view draws a coarser surface of the same model (level
// L-1, 4-point rings): it shows the vessels at ~0.3 mm per pixel, and every triangle costs a
// software rasteriser the same. Empty when `detail_triangles` is below it or meshing fails.
inline constexpr std::size_t kOverviewTriangles = 40'000;
[[nodiscard]] vessel::SurfaceMesh overview_mesh(const vessel::VesselModel& model, std::size_t detail_triangles);

class VesselFollower {
 public:
  // A widened vessel ready to upload. Its views point into `surface` and `overview`: keep it
  // while a renderer may read them (the uploads copy what they need).
  struct Prepared {
    std::uint64_t generation = 0;
    std::shared_ptr<const tool::WallSurface> surface;
    vessel::SurfaceMesh overview;
    SceneRenderer::PreparedVessel scene;
    vessel::SurfaceMesh fluoro_mesh;  // the widened model at fluoro_surface_options() (empty: the wall's mesh)
    std::optional<FluoroVessel> fluoro_vessel;                 // with a contrast transport
    std::optional<FluoroRenderer::VesselBuffers> fluoro;
  };

  VesselFollower() = default;
  ~VesselFollower() { reset(); }
  VesselFollower(const VesselFollower&) = delete;
  VesselFollower& operator=(const VesselFollower&) = delete;

  // After a scene is loaded (the renderers show the case's surface, generation 0) and before the
  // session whose wall is being prepared goes away: waits for a job in progress and drops it.
  void reset();
  // Render thread, once per frame. Starts preparing the session's wall when the snapshot's
  // generation is past the one shown and no job runs; returns the prepared vessel once, when
  // its job is done (it is then the one shown). `transport` (may be null): the session's
  // contrast cells, read by the job for the cell layout only; it must outlive the job. With
  // `wait` the job is waited for (virtual time: the frame shows the wall of its tick).
  [[nodiscard]] std::optional<Prepared> poll(std::uint64_t snapshot_generation, const session::Session& session,
                                             const flow::ContrastTransport* transport, bool wait = false);
  [[nodiscard]] std::uint64_t shown() const { return shown_; }
  [[nodiscard]] bool busy() const { return job_.valid(); }

  // The work of one job (no GL, any thread).
  [[nodiscard]] static Prepared prepare(std::uint64_t generation, std::shared_ptr<const tool::WallSurface> surface,
                                        const flow::ContrastTransport* transport);

 private:
  std::uint64_t shown_ = 0;
  std::uint64_t asked_ = 0;  // the generation of the job in progress
  std::future<std::unique_ptr<Prepared>> job_;
};

}  // namespace cathbox::app

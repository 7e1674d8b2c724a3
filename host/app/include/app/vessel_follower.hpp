#pragma once
// The vessel the views draw follows the simulation's wall. When a balloon has widened the lumen,
// the session swaps a new wall in (SceneSnapshot::wall_generation moves on, Session::wall_surface()
// has the widened model and its mesh); the follower then prepares that surface for the renderers
// on a worker thread while the frames go on drawing the old one: the 3D view's chunks, the global
// view's coarser overview meshed from the widened model, and the fluoroscopic view's contrast-cell
// ties and buffers. The render thread only uploads what is ready (one call per renderer), so no
// frame waits for the meshing, and the haptic thread never sees any of it.
//
// A compliant wall (Session::wall_field()) moves with the pulse: when the snapshot's pressure
// passes into another step of kDrawnPressureStep_kPa, the follower prepares the wall's surface
// moved along its normals by each segment's distension at that step, the same field the
// collision queries read, for the 3D view and the fluoroscopy alike.
//
//   VesselFollower follower;                    // follower.reset() after each scene load
//   each frame: if (auto next = follower.poll(snap.wall_generation, snap.wall_pressure_kPa, session, transport)) {
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
#include "tool/wall_distension.hpp"
#include "tool/wall_model.hpp"
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::app {

// Above this many triangles the global view draws a coarser surface of the same model (level
// L-1, 4-point rings): it shows the vessels at ~0.3 mm per pixel, and every triangle costs a
// software rasteriser the same. Empty when `detail_triangles` is below it or meshing fails.
inline constexpr std::size_t kOverviewTriangles = 40'000;
[[nodiscard]] vessel::SurfaceMesh overview_mesh(const vessel::VesselModel& model, std::size_t detail_triangles);

// The drawn wall follows the pulse in steps of this pressure (0.5 kPa, 3.75 mmHg: ~24 surfaces a
// beat of +-44 mmHg, each a few micrometres of wall from the last).
inline constexpr double kDrawnPressureStep_kPa = 0.5;
// `surface` moved along its vertex normals by `distension` at `pressure_kPa`: each vertex by the
// segment of the first triangle that holds it (junctions by the junctions' displacement).
[[nodiscard]] std::shared_ptr<const tool::WallSurface> distended_surface(const tool::WallSurface& surface,
                                                                         const tool::WallDistension& distension,
                                                                         double pressure_kPa);

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
  // `wall_pressure_kPa`: SceneSnapshot::wall_pressure_kPa (a compliant wall's pulse; 0 without).
  [[nodiscard]] std::optional<Prepared> poll(std::uint64_t snapshot_generation, double wall_pressure_kPa,
                                             const session::Session& session, const flow::ContrastTransport* transport,
                                             bool wait = false);
  [[nodiscard]] std::uint64_t shown() const { return shown_; }
  [[nodiscard]] bool busy() const { return job_.valid(); }

  // The work of one job (no GL, any thread). `as_is`: the surface is drawn as it is (a case's own
  // surface, or one the pulse moved): no coarser re-mesh of its model for the overview or the
  // fluoroscopy, which would draw the centrelines' tubes instead of that wall.
  [[nodiscard]] static Prepared prepare(std::uint64_t generation, std::shared_ptr<const tool::WallSurface> surface,
                                        const flow::ContrastTransport* transport, bool as_is = false);

 private:
  std::uint64_t shown_ = 0;
  std::uint64_t asked_ = 0;  // the generation of the job in progress
  long shown_step_ = 0;      // the pressure step shown and asked (kDrawnPressureStep_kPa)
  long asked_step_ = 0;
  std::future<std::unique_ptr<Prepared>> job_;
};

}  // namespace cathbox::app

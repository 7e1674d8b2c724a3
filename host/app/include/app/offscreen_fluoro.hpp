#pragma once
// The trainer's fluoroscopic view without a visible window: the same FluoroRenderer, fed the same
// way (fluoro_inputs_from_snapshot on the session's newest SceneSnapshot, the case's vessel with
// its contrast cells), drawn into a hidden GL 3.3 window and read back as grey bytes. For programs
// that want the image a trainee sees (the Python environments' image observation). Needs a display
// (Xvfb with Mesa's llvmpipe on a machine without one): create() says so in one line otherwise.
//
//   std::string error;
//   auto view = app::OffscreenFluoro::create(session, 128, 128, error);
//   std::vector<std::uint8_t> grey(128 * 128);
//   error = view->render(session, pose, grey);     // top row first
//
// One thread: the one that created it (GLFW's rule), and the session must outlive it.
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "app/fluoro_frontend.hpp"
#include "app/fluoro_renderer.hpp"
#include "app/fluoro_vessel.hpp"
#include "app/gl_window.hpp"
#include "base/result.hpp"
#include "flow/c_arm.hpp"
#include "session/session.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::app {

class OffscreenFluoro {
 public:
  // Or one line: no display, no GL 3.3, a size outside 8..2048.
  [[nodiscard]] static base::Result<std::unique_ptr<OffscreenFluoro>> create(const session::Session& session, int width,
                                                                             int height);
  // The image of the session's newest snapshot through `pose` into `grey` (width * height bytes,
  // top row first). Empty, or the renderer's one line (the image then black).
  [[nodiscard]] std::string render(session::Session& session, const flow::CArmPose& pose, std::span<std::uint8_t> grey);
  ~OffscreenFluoro();  // its GL objects are deleted in its own context
  OffscreenFluoro(const OffscreenFluoro&) = delete;
  OffscreenFluoro& operator=(const OffscreenFluoro&) = delete;
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }

 private:
  OffscreenFluoro() = default;
  std::unique_ptr<GlWindow> window_;
  FluoroRenderer renderer_;
  vessel::SurfaceMesh mesh_;  // the lumen the contrast fills (FluoroVessel spans it)
  FluoroVessel vessel_;
  SnapshotFluoroSettings settings_;
  int width_ = 0;
  int height_ = 0;
};

}  // namespace cathbox::app

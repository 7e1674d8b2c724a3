#include "app/offscreen_fluoro.hpp"

#include <GLFW/glfw3.h>

#include "app/frame_capture.hpp"
#include "flow/head_phantom.hpp"

namespace cathbox::app {

base::Result<std::unique_ptr<OffscreenFluoro>> OffscreenFluoro::create(const session::Session& session, int width,
                                                                       int height) {
  if (width < 8 || height < 8 || width > 2048 || height > 2048) {
    return base::Error{"fluoroscopy: size " + std::to_string(width) + "x" + std::to_string(height) + " outside 8..2048"};
  }
  std::unique_ptr<OffscreenFluoro> v(new OffscreenFluoro());
  v->width_ = width;
  v->height_ = height;
  base::Result<std::unique_ptr<GlWindow>> window = GlWindow::create(width, height, "cathbox fluoroscopy", false);
  if (!window) {
    return base::Error{"fluoroscopy: " + window.error().message +
                       " (a display is needed: run under xvfb-run on a machine without one)"};
  }
  v->window_ = std::move(*window);
  if (base::Status<> ready = v->renderer_.init(); !ready) return base::Error{"fluoroscopy: " + ready.error().message};
  v->renderer_.set_background_projection(false);  // every image of its own pose, none held
  // The lumen as the trainer draws it: one level coarser than the collision surface, else that one
  // (a case's own surface is drawn as it is).
  const session::SessionCase& scene = session.scene();
  if (const session::FluoroUnit* unit = session.fluoro(); unit != nullptr && scene.mesh() != nullptr) {
    v->mesh_ = scene.model() != nullptr && !scene.surface_given() ? fluoro_surface(*scene.model()) : vessel::SurfaceMesh{};
    v->vessel_ = FluoroVessel::build(v->mesh_.triangle_count() > 0 ? v->mesh_ : *scene.mesh(), unit->transport());
    v->renderer_.set_vessel(v->vessel_);
  }
  return v;
}

OffscreenFluoro::~OffscreenFluoro() {
  if (window_) glfwMakeContextCurrent(window_->handle());  // before renderer_ deletes its objects
}

std::string OffscreenFluoro::render(session::Session& session, const flow::CArmPose& pose, std::span<std::uint8_t> grey) {
  glfwMakeContextCurrent(window_->handle());
  (void)session.snapshots().acquire();
  settings_.pose = pose;
  settings_.patient_transmission = flow::HeadPhantom::neuro().central_transmission(flow::CArm(pose));
  const FluoroInputs inputs = fluoro_inputs_from_snapshot(session.snapshots().read_slot(), settings_);
  std::string error = renderer_.render(Viewport{0, 0, width_, height_}, height_, inputs);
  const Image image = FrameCapture::read_back_buffer(width_, height_);
  for (std::size_t i = 0; i < grey.size() && i < static_cast<std::size_t>(width_ * height_); ++i) {
    grey[i] = image.pixels[i * static_cast<std::size_t>(image.channels)];
  }
  return error;
}

}  // namespace cathbox::app

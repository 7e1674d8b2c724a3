// FluoroRenderer::render and the monitor image: the shown scenes composed with the phantom
// (fluoroscopy, subtraction, roadmap), scaled to the display as a monitor's scaler does.
#include <algorithm>
#include <cmath>

#include "app/fluoro_renderer.hpp"
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "app/gl.hpp"
#include "fluoro_render_parts.hpp"

namespace cathbox::app {

using namespace fluoro_parts;  // the texture units, the hasher

void FluoroRenderer::compose(const FluoroInputs& in, const flow::CArm& carm, bool subtracted, bool roadmap, int w, int h) {
  ensure_target(monitor_, w, h, GL_RGBA8, GL_UNSIGNED_BYTE);
  glBindFramebuffer(GL_FRAMEBUFFER, monitor_.fbo);
  glViewport(0, 0, w, h);
  if (fbfetch_) {
    if (compose_fbo_ == 0) glGenFramebuffers(1, &compose_fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, compose_fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, phantom_texture_, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, monitor_.texture, 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, buffers);
    glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);  // read, never written
  }
  // The scenes' box: inside it the composite reads the scene targets, outside only the phantom.
  scenes_ = targets_[0].drawn;
  if (subtracted) scenes_.unite(targets_[1].drawn);
  if (roadmap) {
    scenes_.unite(targets_[2].drawn);
    scenes_.unite(targets_[3].drawn);
  }
  const int mode = subtracted ? 2 : roadmap ? 1 : 0;
  const flow::FluoroDose dose(in.dose);
  const double pixel_mm = carm.pixel_mm(w, h);
  const auto sigma = [&](const FluoroScene& s) {
    return display_.noise ? static_cast<float>(dose.log_noise_sigma(s.mode, pixel_mm)) : 0.0F;
  };
  const double l_ref = -std::log(std::clamp(in.patient_transmission, 1e-9, 1.0));
  const std::pair<const char*, unsigned> bindings[] = {{"u_phantom", phantom_texture_},
                                                       {"u_live", targets_[0].texture},
                                                       {"u_mask", targets_[1].texture},
                                                       {"u_road", targets_[2].texture},
                                                       {"u_road_mask", targets_[3].texture}};
  for (int unit = kPhantomUnit; unit <= kRoadMaskUnit; ++unit) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
    glBindTexture(GL_TEXTURE_2D, unit == kPhantomUnit && fbfetch_ ? 0 : bindings[unit].second);  // attached: not sampled
  }
  glBindVertexArray(empty_vao_);
  glEnable(GL_SCISSOR_TEST);
  const auto draw = [&](const ShaderProgram& shader, const Rect& r) {
    if (r.empty()) return;
    shader.use();
    for (int unit = kPhantomUnit; unit <= kRoadMaskUnit; ++unit) shader.set_int(bindings[unit].first, unit);
    shader.set("u_view", glm::vec4(0.0F, 0.0F, static_cast<float>(w), static_cast<float>(h)));
    shader.set("u_sigma", glm::vec4(sigma(in.shown), sigma(in.mask), sigma(in.roadmap), sigma(in.roadmap_mask)));
    shader.set("u_seeds", glm::uvec4(pulse_seed(in.shown.pulse), pulse_seed(in.mask.pulse), pulse_seed(in.roadmap.pulse),
                                     pulse_seed(in.roadmap_mask.pulse)));
    shader.set("u_display", glm::vec4(display_.fluoro_slope, display_.dsa_background, display_.dsa_gain, display_.roadmap_gain));
    shader.set("u_mode", glm::vec4(0.0F, 0.0F, 0.0F, static_cast<float>(l_ref)));
    shader.set("u_anatomy_gain", display_.anatomy_gain);
    shader.set("u_field_half", static_cast<float>(0.5 * std::min(w, h) * in.pose.collimation));
    glScissor(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  };
  // Inside the scenes' cells the scene targets are read; the rest of the image reads the phantom alone.
  for (const Rect& r : scenes_.runs(true)) draw(composite_shaders_[static_cast<std::size_t>(mode)], r);
  for (const Rect& r : scenes_.runs(false)) draw(composite_shaders_[static_cast<std::size_t>(mode + 3)], r);
  glDisable(GL_SCISSOR_TEST);
  glBindVertexArray(0);
  if (fbfetch_) {
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);  // free to be re-specified
  }
  for (int unit = kRoadMaskUnit; unit >= kPhantomUnit; --unit) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
    glBindTexture(GL_TEXTURE_2D, 0);
  }
  ++work_.composites;
}

FluoroRenderer::Matrix FluoroRenderer::matrix(const flow::CArm& carm, int width, int height, flow::ExposureMode mode) const {
  const double pitch = mode == flow::ExposureMode::kFluoroscopy ? display_.fluoro_readout_pitch_mm : 0.0;
  const ImageMatrix m = readout_matrix(width, height, carm.pixel_mm(width, height), pitch);
  return {m.width, m.height};
}

void FluoroRenderer::scale(const Target& source, unsigned fbo, int x, int y, int width, int height) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(x, y, width, height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(x, y, width, height);
  scale_shader_.use();
  scale_shader_.set_int("u_image", 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, source.texture);
  glBindSampler(0, linear_sampler_);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindSampler(0, 0);
  glBindTexture(GL_TEXTURE_2D, 0);
  glDisable(GL_SCISSOR_TEST);
}

// The GL state render() changes and gives back: the draw framebuffer, scissor and depth test.
struct FluoroRenderer::SavedGlState {
  GLint fbo = 0;
  GLboolean scissor = GL_FALSE;
  GLboolean depth = GL_FALSE;

  static SavedGlState save() {
    SavedGlState s;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s.fbo);
    s.scissor = glIsEnabled(GL_SCISSOR_TEST);
    s.depth = glIsEnabled(GL_DEPTH_TEST);
    return s;
  }
  void restore() const {
    glActiveTexture(GL_TEXTURE0);
    if (scissor == GL_TRUE) {
      glEnable(GL_SCISSOR_TEST);
    } else {
      glDisable(GL_SCISSOR_TEST);
    }
    if (depth == GL_TRUE) glEnable(GL_DEPTH_TEST);
  }
};

std::string FluoroRenderer::render(const Viewport& viewport, int framebuffer_height, const FluoroInputs& in) {
  work_ = {};
  std::string error = check_fluoro_inputs(in, vessel_indices_ > 0 ? cell_count_ : 0);
  if (viewport.width <= 0 || viewport.height <= 0) return error;  // a minimised window: nothing to draw
  const flow::CArm carm(in.pose);
  const flow::FluoroImage& image = in.image;
  const bool has_image = error.empty() && image.pulse >= 0 && in.shown.pulse >= 0;
  Shown shown;
  shown.subtracted = has_image && image.subtracted() && in.mask.pulse >= 0;
  shown.roadmap = has_image && !shown.subtracted && image.roadmap_pulse >= 0 && in.roadmap.pulse >= 0 && in.roadmap_mask.pulse >= 0;
  // The image's pixels: the detector's readout (binned in fluoroscopy), never finer than the display's.
  const Matrix m = matrix(carm, viewport.width, viewport.height, in.shown.mode);
  work_.matrix_width = m.width;
  work_.matrix_height = m.height;
  const SavedGlState saved = SavedGlState::save();
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  const auto previous_fbo = static_cast<GLuint>(saved.fbo);
  const int gl_y = framebuffer_height - viewport.y - viewport.height;
  if (!has_image) {  // before the first pulse the monitor is black
    glBindFramebuffer(GL_FRAMEBUFFER, previous_fbo);
    glEnable(GL_SCISSOR_TEST);
    glScissor(viewport.x, gl_y, viewport.width, viewport.height);
    glClearColor(0.0F, 0.0F, 0.0F, 1.0F);
    glClear(GL_COLOR_BUFFER_BIT);
  } else {
    // While the phantom of a new pose is projected in the background the last image stays.
    const flow::ExposureMode other_mode =
        in.shown.mode == flow::ExposureMode::kFluoroscopy ? flow::ExposureMode::kSubtractionRun : flow::ExposureMode::kFluoroscopy;
    if (project_phantom(carm, m, matrix(carm, viewport.width, viewport.height, other_mode),
                        -std::log(std::clamp(in.patient_transmission, 1e-9, 1.0)))) {
      update_monitor(in, carm, shown, m);
    }
    show_monitor(viewport, gl_y, previous_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, previous_fbo);
  }
  saved.restore();
  return error;
}

// The scenes accumulated again where they changed, and the monitor image composed again when
// anything it shows changed.
void FluoroRenderer::update_monitor(const FluoroInputs& in, const flow::CArm& carm, const Shown& shown, const Matrix& m) {
  const double keV = in.dose.effective_keV;
  const int w = m.width;
  const int h = m.height;
  accumulate(targets_[0], in.shown, carm, keV, w, h);
  if (shown.subtracted) accumulate(targets_[1], in.mask, carm, keV, w, h);
  if (shown.roadmap) {
    accumulate(targets_[2], in.roadmap, carm, keV, w, h);
    accumulate(targets_[3], in.roadmap_mask, carm, keV, w, h);
  }
  const std::uint64_t key = monitor_key(in, shown);
  if (!monitor_.valid || monitor_.key != key || monitor_.width != w || monitor_.height != h) {
    compose(in, carm, shown.subtracted, shown.roadmap, w, h);
    monitor_.key = key;
    monitor_.valid = true;
  }
}

// The monitor image changes only with a new pulse, a new roadmap, the pose or the display:
// otherwise (last-image hold, frames between pulses) it is copied again.
std::uint64_t FluoroRenderer::monitor_key(const FluoroInputs& in, const Shown& shown) const {
  Hasher k;
  k.add(projections_.key());
  k.add(phantom_l_ref_);
  for (int i = 0; i < 4; ++i) {
    const bool used = i == 0 || (i == 1 && shown.subtracted) || (i >= 2 && shown.roadmap);
    k.add(used ? targets_[static_cast<std::size_t>(i)].key : 0);
  }
  for (const FluoroScene* s : {&in.shown, &in.mask, &in.roadmap, &in.roadmap_mask}) {
    k.add(s->pulse);
    k.add(s->mode);
  }
  k.add(shown.subtracted);
  k.add(shown.roadmap);
  k.add(in.patient_transmission);
  k.add_bytes(&in.dose, sizeof in.dose);
  k.add_bytes(&display_, sizeof display_);
  return k.digest();
}

// The monitor image into the viewport of framebuffer `fbo` (GL row `gl_y`). A binned image is
// scaled to the display's size, bilinear as a monitor's scaler does (a draw, scale(): on
// llvmpipe at 1024^2 ~6 ms of CPU, a plain copy ~4, a scaled blit ~9.5). An image is scaled
// straight into the window for its first kDirectShows showings (a pulse and the display frames
// until the next one, up to 15 pulses/s at 60 Hz; scaling into `scaled_` and copying it would
// cost ~10 at the first); shown more often (last-image hold) it is scaled once into `scaled_`,
// and from then on copied plainly.
void FluoroRenderer::show_monitor(const Viewport& viewport, int gl_y, unsigned fbo) {
  constexpr int kDirectShows = 4;
  shows_ = monitor_.key == shown_key_ ? shows_ + 1 : 1;
  shown_key_ = monitor_.key;
  const bool scaled = monitor_.width != viewport.width || monitor_.height != viewport.height;
  const Target* source = &monitor_;
  if (scaled && shows_ > kDirectShows) {
    if (!scaled_.valid || scaled_.key != monitor_.key || scaled_.width != viewport.width || scaled_.height != viewport.height) {
      ensure_target(scaled_, viewport.width, viewport.height, GL_RGBA8, GL_UNSIGNED_BYTE);
      scale(monitor_, scaled_.fbo, 0, 0, viewport.width, viewport.height);
      scaled_.key = monitor_.key;
      scaled_.valid = true;
    }
    source = &scaled_;
  }
  if (source->width != viewport.width || source->height != viewport.height) {
    scale(*source, fbo, viewport.x, gl_y, viewport.width, viewport.height);
  } else {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, source->fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glBlitFramebuffer(0, 0, source->width, source->height, viewport.x, gl_y, viewport.x + viewport.width, gl_y + viewport.height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
}

}  // namespace cathbox::app

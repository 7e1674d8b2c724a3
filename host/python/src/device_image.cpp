#include "python/device_image.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::python {
namespace {

// Per pixel of one tool: the largest chord (mm on the detector) of its tube through the pixel.
void draw_tube(const tool::ToolSnapshot& t, const flow::CArm& arm, int w, int h, float* chord) {
  const double px_mm = arm.pixel_mm(w, h);
  const std::size_t n = t.positions_mm.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const glm::dvec3& p0 = t.positions_mm[i];
    const glm::dvec3& p1 = t.positions_mm[i + 1];
    if (arm.depth_mm(p0) <= 0.0 || arm.depth_mm(p1) <= 0.0) continue;
    const glm::dvec2 a = arm.project_px(p0, w, h);
    const glm::dvec2 b = arm.project_px(p1, w, h);
    const double radius_mm = t.radii_mm.size() > i ? static_cast<double>(t.radii_mm[i]) : 0.2;
    const double r_px = std::max(0.5, radius_mm * arm.magnification(p0) / px_mm);
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a.x, b.x) - r_px)));
    const int x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max(a.x, b.x) + r_px)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a.y, b.y) - r_px)));
    const int y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max(a.y, b.y) + r_px)));
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const glm::dvec2 p{x + 0.5, y + 0.5};
        const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
        const glm::dvec2 d = p - (a + s * ab);
        const double d2 = glm::dot(d, d);
        if (d2 >= r_px * r_px) continue;
        const auto c = static_cast<float>(2.0 * std::sqrt(r_px * r_px - d2) * px_mm);
        float& cell = chord[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
        cell = std::max(cell, c);
      }
    }
  }
}

}  // namespace

void render_device_image(const tool::Snapshot& state, const flow::CArm& c_arm, int width, int height,
                         std::span<std::uint8_t> out, std::vector<float>& scratch, const DeviceImageSettings& settings) {
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  scratch.assign(2 * pixels, 0.0F);  // optical depth, then one tool's chords
  float* depth = scratch.data();
  float* chord = scratch.data() + pixels;
  for (const tool::ToolSnapshot& t : state.tools) {
    std::fill(chord, chord + pixels, 0.0F);
    draw_tube(t, c_arm, width, height, chord);
    const auto mu =
        static_cast<float>(tool::is_catheter(t.kind) ? settings.catheter_mu_per_mm : settings.guidewire_mu_per_mm);
    for (std::size_t i = 0; i < pixels; ++i) depth[i] += mu * chord[i];
  }
  for (std::size_t i = 0; i < pixels && i < out.size(); ++i) {
    const float v = settings.field * std::exp(-depth[i]);
    out[i] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0F, 1.0F) * 255.0F));
  }
}

}  // namespace cathbox::python

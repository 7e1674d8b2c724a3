#pragma once
// The case picker's anatomy thumbnail: the vessel's centreline pieces drawn as shaded tubes of
// their radius in an orthographic AP projection (patient coordinates as the bundled cases: x to
// the patient's left = image right, z superior = image up, y anterior = towards the viewer),
// fitted into a square image, the target marked. A CPU rasteriser: no GL, so it runs anywhere
// and is tested pixel for pixel.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "app/png_writer.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::app {

// One straight piece of a vessel (its ends on the centreline, the lumen radius at each): the
// case module's analytic tube, also made from an HCLM's centreline (case_summary.hpp).
using ThumbnailTube = tool::Tube;

// Where a patient point lands in the thumbnail: uniform scale, the tubes' extent (with their
// radii) centred with a margin.
class ThumbnailProjection {
 public:
  ThumbnailProjection() = default;
  // Fits `tubes` into `size_px` x `size_px` with `margin_px` on every side.
  [[nodiscard]] static ThumbnailProjection fit(const std::vector<ThumbnailTube>& tubes, int size_px, double margin_px);
  [[nodiscard]] glm::dvec2 to_px(const glm::dvec3& p_mm) const;  // pixel centres at (i + 0.5, j + 0.5)
  [[nodiscard]] double px_per_mm() const { return px_per_mm_; }

 private:
  glm::dvec2 centre_mm_{0.0};  // (x, z) at the image centre
  double half_size_px_ = 0.0;
  double px_per_mm_ = 1.0;
};

struct ThumbnailColors {
  static constexpr std::uint8_t kBackground[3] = {22, 26, 32};
  static constexpr std::uint8_t kVessel[3] = {214, 92, 78};
  static constexpr std::uint8_t kTarget[3] = {250, 214, 60};
};

struct Thumbnail {
  Image image;  // RGBA, opaque
  ThumbnailProjection projection;
};

// Draws the tubes (nearer ones over farther ones, each shaded as a cylinder lit from the
// viewer; at least 1 px wide so small branches show) and, when given, a ring round the target.
// The view is fitted to all the tubes, or with a target to those within 50 mm of it (the part
// of the anatomy the case is about; the rest is cut at the image's edge). No tubes: the
// background alone.
[[nodiscard]] Thumbnail render_thumbnail(const std::vector<ThumbnailTube>& tubes, const std::optional<glm::dvec3>& target_mm,
                                         int size_px);

}  // namespace cathbox::app

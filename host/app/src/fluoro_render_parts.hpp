#pragma once
// What the FluoroRenderer's files share: the texture units its shaders read, its cache keys'
// hashing, and the screen box of what a scene draws.
#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "app/fluoro_renderer.hpp"
#include "base/xxh_hasher.hpp"

namespace cathbox::app::fluoro_parts {

enum Unit : int { kPhantomUnit = 0, kLiveUnit, kMaskUnit, kRoadUnit, kRoadMaskUnit, kCellsUnit };

// What a scene target depends on is hashed with the project's one hasher (XXH3); the pose by
// hash_pose (app/fluoro_inputs.hpp).
using Hasher = base::XxhHasher;

}  // namespace cathbox::app::fluoro_parts

namespace cathbox::app {

// Bounding box on screen of what a scene draws, in GL pixels of a width x height target
// (conservative: a pixel and a half of margin).
class FluoroRenderer::ScreenBox {
 public:
  ScreenBox(const flow::CArm& carm, int width, int height)
      : carm_(carm), width_(width), height_(height), px_per_mm_(1.0 / carm.pixel_mm(width, height)) {}
  // A sphere: its centre's projection and its radius magnified at its depth.
  void add_sphere(const glm::vec3& c, float radius_mm) {
    const glm::dvec3 p(c);
    add_point(carm_.project_px(p, width_, height_), radius_mm * carm_.magnification(p) * px_per_mm_);
  }
  // An axis-aligned box: the projections of its corners (a projection keeps convex hulls).
  void add_box(const glm::vec3& lo, const glm::vec3& hi) {
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 p((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y, (k & 4) != 0 ? hi.z : lo.z);
      add_point(carm_.project_px(p, width_, height_), 0.0);
    }
  }
  [[nodiscard]] Rect rect() const {
    if (lo_.x > hi_.x) return {};
    constexpr double kMargin = 1.5;
    // project_px: y down from the top edge; GL rows count up from the bottom.
    Rect r{static_cast<int>(std::floor(lo_.x - kMargin)), static_cast<int>(std::floor(height_ - hi_.y - kMargin)),
           static_cast<int>(std::ceil(hi_.x + kMargin)), static_cast<int>(std::ceil(height_ - lo_.y + kMargin))};
    r.x0 = std::clamp(r.x0, 0, width_);
    r.x1 = std::clamp(r.x1, 0, width_);
    r.y0 = std::clamp(r.y0, 0, height_);
    r.y1 = std::clamp(r.y1, 0, height_);
    return r.empty() ? Rect{} : r;
  }

 private:
  void add_point(glm::dvec2 p, double radius_px) {
    lo_ = glm::min(lo_, p - radius_px);
    hi_ = glm::max(hi_, p + radius_px);
  }
  const flow::CArm& carm_;
  int width_;
  int height_;
  double px_per_mm_;
  glm::dvec2 lo_{1e30};
  glm::dvec2 hi_{-1e30};
};

}  // namespace cathbox::app

#include "app/case_thumbnail.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

namespace cathbox::app {
namespace {

constexpr double kMinRadius_px = 0.5;   // a branch thinner than a pixel still draws one pixel wide
constexpr double kTargetRing_px = 4.5;  // the target's ring: at least this radius
constexpr double kRingHalfWidth_px = 0.9;
constexpr double kFocus_mm = 50.0;      // with a target: the view is fitted to the vessels this near it

// What the tubes leave in one pixel: the nearest surface's depth and shade, and how much of
// the pixel the tubes cover (for smooth edges).
struct Fragment {
  double depth = -std::numeric_limits<double>::infinity();
  double shade = 0.0;
  double coverage = 0.0;
};

struct TubePx {
  glm::dvec2 a;
  glm::dvec2 b;
  double depth_a = 0.0;  // y (anterior, towards the viewer) in pixels
  double depth_b = 0.0;
  double radius_a = 0.0;
  double radius_b = 0.0;
};

TubePx to_pixels(const ThumbnailTube& t, const ThumbnailProjection& proj) {
  const double s = proj.px_per_mm();
  return {proj.to_px(t.a_mm),      proj.to_px(t.b_mm),
          t.a_mm.y * s,            t.b_mm.y * s,
          std::max(t.radius_a_mm * s, kMinRadius_px), std::max(t.radius_b_mm * s, kMinRadius_px)};
}

// One tube piece into the fragments: each pixel centre within its radius of the projected
// axis, shaded as a cylinder seen from the front, nearer surfaces winning.
void draw_tube(const TubePx& t, int size, std::vector<Fragment>& frags) {
  const double r_max = std::max(t.radius_a, t.radius_b) + 1.0;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min(t.a.x, t.b.x) - r_max)));
  const int x1 = std::min(size - 1, static_cast<int>(std::ceil(std::max(t.a.x, t.b.x) + r_max)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min(t.a.y, t.b.y) - r_max)));
  const int y1 = std::min(size - 1, static_cast<int>(std::ceil(std::max(t.a.y, t.b.y) + r_max)));
  const glm::dvec2 d = t.b - t.a;
  const double len2 = glm::dot(d, d);
  for (int j = y0; j <= y1; ++j) {
    for (int i = x0; i <= x1; ++i) {
      const glm::dvec2 p{i + 0.5, j + 0.5};
      const double u = len2 > 0.0 ? std::clamp(glm::dot(p - t.a, d) / len2, 0.0, 1.0) : 0.0;
      const double dist = glm::length(p - (t.a + u * d));
      const double r = t.radius_a + u * (t.radius_b - t.radius_a);
      const double coverage = std::clamp(r + 0.5 - dist, 0.0, 1.0);
      if (coverage <= 0.0) continue;
      const double facing = std::sqrt(std::max(0.0, 1.0 - (dist / r) * (dist / r)));
      const double depth = t.depth_a + u * (t.depth_b - t.depth_a) + r * facing;
      Fragment& f = frags[static_cast<std::size_t>(j) * static_cast<std::size_t>(size) + static_cast<std::size_t>(i)];
      f.coverage = std::max(f.coverage, coverage);
      if (depth <= f.depth) continue;
      f.depth = depth;
      f.shade = 0.35 + 0.65 * facing;
    }
  }
}

void put(Image& img, int i, int j, const std::uint8_t (&rgb)[3], double weight) {
  std::uint8_t* px = img.pixels.data() + (static_cast<std::size_t>(j) * static_cast<std::size_t>(img.width) +
                                          static_cast<std::size_t>(i)) * 4U;
  for (int c = 0; c < 3; ++c) {
    px[c] = static_cast<std::uint8_t>(std::lround((1.0 - weight) * px[c] + weight * rgb[c]));
  }
}

// A ring round the target, over the tubes.
void draw_target(Image& img, const glm::dvec2& c, double radius) {
  const int lo_x = std::max(0, static_cast<int>(c.x - radius - 2.0));
  const int hi_x = std::min(img.width - 1, static_cast<int>(c.x + radius + 2.0));
  const int lo_y = std::max(0, static_cast<int>(c.y - radius - 2.0));
  const int hi_y = std::min(img.height - 1, static_cast<int>(c.y + radius + 2.0));
  for (int j = lo_y; j <= hi_y; ++j) {
    for (int i = lo_x; i <= hi_x; ++i) {
      const double off = std::abs(glm::length(glm::dvec2{i + 0.5, j + 0.5} - c) - radius);
      const double w = std::clamp(kRingHalfWidth_px + 0.5 - off, 0.0, 1.0);
      if (w > 0.0) put(img, i, j, ThumbnailColors::kTarget, w);
    }
  }
}

}  // namespace

ThumbnailProjection ThumbnailProjection::fit(const std::vector<ThumbnailTube>& tubes, int size_px, double margin_px) {
  ThumbnailProjection p;
  p.half_size_px_ = 0.5 * size_px;
  if (tubes.empty()) return p;
  glm::dvec2 lo{std::numeric_limits<double>::infinity()};
  glm::dvec2 hi{-std::numeric_limits<double>::infinity()};
  for (const ThumbnailTube& t : tubes) {
    for (const auto& [pos, r] : {std::pair{t.a_mm, t.radius_a_mm}, std::pair{t.b_mm, t.radius_b_mm}}) {
      lo = glm::min(lo, glm::dvec2{pos.x, pos.z} - r);
      hi = glm::max(hi, glm::dvec2{pos.x, pos.z} + r);
    }
  }
  const double span_mm = std::max(hi.x - lo.x, hi.y - lo.y);
  const double room_px = std::max(1.0, size_px - 2.0 * margin_px);
  p.px_per_mm_ = span_mm > 0.0 ? room_px / span_mm : 1.0;
  p.centre_mm_ = 0.5 * (lo + hi);
  return p;
}

glm::dvec2 ThumbnailProjection::to_px(const glm::dvec3& p_mm) const {
  return {half_size_px_ + (p_mm.x - centre_mm_.x) * px_per_mm_, half_size_px_ - (p_mm.z - centre_mm_.y) * px_per_mm_};
}

namespace {

// The tubes the view is fitted to: with a target, those with an end within kFocus_mm of it
// (the part of the anatomy the case is about); else, or when none is that near, all.
std::vector<ThumbnailTube> framed_tubes(const std::vector<ThumbnailTube>& tubes, const std::optional<glm::dvec3>& target_mm) {
  if (!target_mm) return tubes;
  std::vector<ThumbnailTube> near;
  for (const ThumbnailTube& t : tubes) {
    if (glm::length(t.a_mm - *target_mm) <= kFocus_mm || glm::length(t.b_mm - *target_mm) <= kFocus_mm) near.push_back(t);
  }
  return near.empty() ? tubes : near;
}

}  // namespace

Thumbnail render_thumbnail(const std::vector<ThumbnailTube>& tubes, const std::optional<glm::dvec3>& target_mm, int size_px) {
  Thumbnail out;
  const int size = std::max(size_px, 1);
  out.projection = ThumbnailProjection::fit(framed_tubes(tubes, target_mm), size, std::max(2.0, size * 0.05));
  std::vector<Fragment> frags(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
  for (const ThumbnailTube& t : tubes) draw_tube(to_pixels(t, out.projection), size, frags);
  Image& img = out.image;
  img.width = size;
  img.height = size;
  img.channels = 4;
  img.pixels.assign(frags.size() * 4U, 255);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      put(img, i, j, ThumbnailColors::kBackground, 1.0);
      const Fragment& f = frags[static_cast<std::size_t>(j) * static_cast<std::size_t>(size) + static_cast<std::size_t>(i)];
      if (f.coverage <= 0.0) continue;
      const std::uint8_t shaded[3] = {static_cast<std::uint8_t>(ThumbnailColors::kVessel[0] * f.shade),
                                      static_cast<std::uint8_t>(ThumbnailColors::kVessel[1] * f.shade),
                                      static_cast<std::uint8_t>(ThumbnailColors::kVessel[2] * f.shade)};
      put(img, i, j, shaded, f.coverage);
    }
  }
  if (target_mm) draw_target(img, out.projection.to_px(*target_mm), kTargetRing_px);
  return out;
}

}  // namespace cathbox::app

#include "tool/displaced_wall.hpp"

#include <algorithm>

namespace cathbox::tool {

void DisplacedWall::set_uniform_mm(double w_mm) {
  if (w_mm != uniform_mm_) ++revision_;
  uniform_mm_ = w_mm;
  largest_mm_ = std::max(0.0, w_mm);
  for (std::size_t s = 0; s < segment_mm_.size(); ++s) {
    if (segment_set_[s]) largest_mm_ = std::max(largest_mm_, segment_mm_[s]);
  }
}

void DisplacedWall::set_segment_mm(std::int32_t segment, double w_mm) {
  if (segment < 0) return;
  const auto s = static_cast<std::size_t>(segment);
  if (segment_mm_.size() <= s) {
    segment_mm_.resize(s + 1, 0.0);
    segment_set_.resize(s + 1, 0);
  }
  if (segment_mm_[s] != w_mm || segment_set_[s] == 0) ++revision_;
  segment_mm_[s] = w_mm;
  segment_set_[s] = 1;
  largest_mm_ = std::max(largest_mm_, w_mm);
}

double DisplacedWall::displacement_mm(std::int32_t segment) const {
  if (segment < 0) return uniform_mm_;
  const auto s = static_cast<std::size_t>(segment);
  return s < segment_mm_.size() && segment_set_[s] ? segment_mm_[s] : uniform_mm_;
}

bool DisplacedWall::probe(const WallProbe& probe, WallHint& hint, WallContact& out) const {
  WallProbe widened = probe;
  widened.range_mm = probe.range_mm + largest_mm_;
  if (!inner_.probe(widened, hint, out)) return false;
  const double w = displacement_mm(out.segment);
  out.point_mm += out.normal * w;
  out.distance_mm += w;
  if (out.has_second) out.second_point_mm += out.second_normal * w;
  // Within range of the moved wall, or outside the lumen.
  return out.distance_mm - probe.radius_mm <= probe.range_mm || out.distance_mm < 0.0;
}

}  // namespace cathbox::tool

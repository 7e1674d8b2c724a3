#include "app/frame_stats.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace cathbox::app {

double FrameStats::percentile_us(double p) const {
  if (frames_us_.empty()) return 0.0;
  std::vector<std::int64_t> v = frames_us_;
  std::sort(v.begin(), v.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  const double f = rank - static_cast<double>(lo);
  return static_cast<double>(v[lo]) * (1.0 - f) + static_cast<double>(v[hi]) * f;
}

double FrameStats::mean_fps() const {
  if (frames_us_.empty()) return 0.0;
  const double total = static_cast<double>(std::accumulate(frames_us_.begin(), frames_us_.end(), std::int64_t{0}));
  return total > 0.0 ? 1e6 * static_cast<double>(frames_us_.size()) / total : 0.0;
}

}  // namespace cathbox::app

#include "vessel/radius_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace cathbox::vessel {
namespace {

[[nodiscard]] bool usable(double r) { return std::isfinite(r) && r > 0.0; }

// The median of v (reordered); v is not empty.
[[nodiscard]] double median(std::vector<double>& v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

}  // namespace

std::string RadiusFilterReport::summary() const {
  if (changed == 0) return "changed no radius";
  char buf[128];
  std::snprintf(buf, sizeof buf, "changed %zu of %zu radii in %zu segments (max %.0f %%)", changed, points,
                segments_changed, 100.0 * max_relative_change);
  return buf;
}

RadiusFilterReport filter_radii(VesselModel& model) {
  RadiusFilterReport report;
  std::vector<double> original, window, deviation;
  for (Segment& segment : model.segments) {
    auto& points = segment.points;
    const std::size_t n = points.size();
    report.points += n;
    original.resize(n);
    bool any_usable = false;
    for (std::size_t i = 0; i < n; ++i) {
      original[i] = points[i].radius_mm;
      any_usable = any_usable || usable(original[i]);
    }
    if (!any_usable) {
      ++report.unusable_segments;
      continue;
    }
    const auto width = static_cast<std::size_t>(2 * kRadiusWindow + 1);
    bool segment_changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      // The window around i, shifted inward at the ends; widened until it holds a usable radius.
      std::size_t begin = i >= static_cast<std::size_t>(kRadiusWindow) ? i - kRadiusWindow : 0;
      if (begin + width > n) begin = n > width ? n - width : 0;
      std::size_t end = std::min(n, begin + width);
      window.clear();
      for (;;) {
        for (std::size_t j = begin; j < end; ++j) {
          if (usable(original[j])) window.push_back(original[j]);
        }
        if (!window.empty() || (begin == 0 && end == n)) break;
        window.clear();
        begin = begin > 0 ? begin - 1 : 0;
        end = std::min(n, end + 1);
      }
      const double m = median(window);
      deviation.clear();
      for (double r : window) deviation.push_back(std::abs(r - m));
      const double spread = 1.4826 * median(deviation);
      const double r = original[i];
      if (usable(r) && std::abs(r - m) <= std::max(kRadiusSigmas * spread, kRadiusMinRelative * m)) continue;
      points[i].radius_mm = m;
      ++report.changed;
      segment_changed = true;
      report.max_relative_change = std::max(report.max_relative_change, usable(r) ? std::abs(m - r) / m : 1.0);
    }
    if (segment_changed) ++report.segments_changed;
  }
  return report;
}

}  // namespace cathbox::vessel

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

// The usable radii of the window around i (2 kRadiusWindow + 1 points, shifted inward at the
// ends), widened until it holds one (`original` has at least one usable radius).
void usable_window(const std::vector<double>& original, std::size_t i, std::vector<double>& window) {
  const std::size_t n = original.size();
  const auto width = static_cast<std::size_t>(2 * kRadiusWindow + 1);
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
}

// Scratch vectors reused across segments.
struct FilterScratch {
  std::vector<double> original, window, deviation;
};

// Replaces the segment's outlying and unusable radii by their window's median; returns whether
// it changed any.
bool filter_segment(Segment& segment, FilterScratch& scratch, RadiusFilterReport& report) {
  auto& points = segment.points;
  const std::size_t n = points.size();
  bool segment_changed = false;
  for (std::size_t i = 0; i < n; ++i) {
    usable_window(scratch.original, i, scratch.window);
    const double m = median(scratch.window);
    scratch.deviation.clear();
    for (double r : scratch.window) scratch.deviation.push_back(std::abs(r - m));
    const double spread = 1.4826 * median(scratch.deviation);
    const double r = scratch.original[i];
    if (usable(r) && std::abs(r - m) <= std::max(kRadiusSigmas * spread, kRadiusMinRelative * m)) continue;
    points[i].radius_mm = m;
    ++report.changed;
    segment_changed = true;
    report.max_relative_change = std::max(report.max_relative_change, usable(r) ? std::abs(m - r) / m : 1.0);
  }
  return segment_changed;
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
  FilterScratch scratch;
  for (Segment& segment : model.segments) {
    const std::size_t n = segment.points.size();
    report.points += n;
    scratch.original.resize(n);
    bool any_usable = false;
    for (std::size_t i = 0; i < n; ++i) {
      scratch.original[i] = segment.points[i].radius_mm;
      any_usable = any_usable || usable(scratch.original[i]);
    }
    if (!any_usable) {
      ++report.unusable_segments;
      continue;
    }
    if (filter_segment(segment, scratch, report)) ++report.segments_changed;
  }
  return report;
}

}  // namespace cathbox::vessel

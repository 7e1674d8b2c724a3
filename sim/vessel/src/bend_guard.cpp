#include "vessel/bend_guard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "vessel/centerline_smoother.hpp"
#include "vessel/mesh_options.hpp"

namespace cathbox::vessel {
namespace {

constexpr int kMaxPasses = 4000;  // a 90-degree corner at a tenth of a radius spacing needs ~1000
constexpr std::ptrdiff_t kWindow = 2;  // points on each side of a tight one that are relaxed with it

// The circle through the point and its neighbours, over the point's radius.
[[nodiscard]] double bend_over_radius(const std::vector<CenterlinePoint>& points, std::size_t i) {
  const glm::dvec3 a = points[i - 1].pos_mm - points[i].pos_mm;
  const glm::dvec3 b = points[i + 1].pos_mm - points[i].pos_mm;
  const double la = glm::length(a);
  const double lb = glm::length(b);
  // A repeated point, or a radius no bend can be measured against (validation refuses it).
  if (la <= 0.0 || lb <= 0.0 || !(points[i].radius_mm > 0.0)) return std::numeric_limits<double>::infinity();
  const double twice_area = glm::length(glm::cross(a, b));
  if (twice_area <= 1e-12 * la * lb) {  // collinear: straight on, or folded straight back
    return glm::dot(a, b) < 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  }
  return la * lb * glm::length(a - b) / (2.0 * twice_area) / points[i].radius_mm;
}

// The inner points within kWindow of a bend tighter than the bound.
[[nodiscard]] std::vector<char> tight_windows(const std::vector<CenterlinePoint>& points, double bound, bool& any) {
  const auto n = static_cast<std::ptrdiff_t>(points.size());
  std::vector<char> relax(points.size(), 0);
  any = false;
  for (std::ptrdiff_t i = 1; i + 1 < n; ++i) {
    if (bend_over_radius(points, static_cast<std::size_t>(i)) >= bound) continue;
    any = true;
    for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(1, i - kWindow); j <= std::min(n - 2, i + kWindow); ++j) {
      relax[static_cast<std::size_t>(j)] = 1;
    }
  }
  return relax;
}

[[nodiscard]] double tightest(const std::vector<CenterlinePoint>& points) {
  double out = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i + 1 < points.size(); ++i) out = std::min(out, bend_over_radius(points, i));
  return out;
}

}  // namespace

std::vector<CenterlinePoint> swept_centerline(const Segment& segment) {
  const MeshOptions defaults;
  std::vector<CenterlinePoint> points = segment.points;
  for (int pass = 0; pass < defaults.smoothing_passes; ++pass) {
    if (defaults.smoothing == SmoothingMethod::kTaubin) taubin_polyline(points);
    else smooth_polyline(points);
  }
  return points;
}

double tightest_bend_over_radius(const Segment& segment) { return tightest(segment.points); }

double tightest_swept_bend_over_radius(const Segment& segment) { return tightest(swept_centerline(segment)); }

BendGuardReport round_tight_bends(VesselModel& model, double min_bend_radii) {
  BendGuardReport report;
  report.bound = min_bend_radii;
  report.tightest_before = std::numeric_limits<double>::infinity();
  for (Segment& segment : model.segments) {
    std::vector<CenterlinePoint>& points = segment.points;
    const double swept = tightest_swept_bend_over_radius(segment);
    if (swept >= min_bend_radii) continue;
    ++report.bends;
    report.tightest_before = std::min(report.tightest_before, swept);
    const std::vector<CenterlinePoint> before = points;
    bool tight = true;
    for (int pass = 0; pass < kMaxPasses && tight; ++pass) {
      // Measured on the centreline the mesher sweeps, relaxed on the one it is given (the same points).
      const std::vector<char> relax = tight_windows(swept_centerline(segment), min_bend_radii, tight);
      if (!tight) break;
      const std::vector<CenterlinePoint> last = points;
      for (std::size_t i = 1; i + 1 < points.size(); ++i) {
        if (relax[i] != 0) points[i].pos_mm += 0.25 * (last[i - 1].pos_mm + last[i + 1].pos_mm - 2.0 * last[i].pos_mm);
      }
    }
    if (tight) ++report.left_tight;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double moved = glm::length(points[i].pos_mm - before[i].pos_mm);
      if (moved > 0.0) ++report.points_moved;
      report.max_move_mm = std::max(report.max_move_mm, moved);
    }
  }
  if (report.bends == 0) report.tightest_before = 0.0;
  return report;
}

std::string BendGuardReport::summary() const {
  if (bends == 0) return {};
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "%zu bend%s tighter than %.2g lumen radii rounded (tightest %.3g radii; %zu points moved up to %.3g mm)",
                bends, bends == 1 ? "" : "s", bound, tightest_before, points_moved, max_move_mm);
  std::string out = buffer;
  if (left_tight > 0) out += "; WARNING: " + std::to_string(left_tight) + " still tighter (the wall may fold there)";
  return out;
}

}  // namespace cathbox::vessel

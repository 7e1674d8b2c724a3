#include "vessel/centerline_smoother.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::vessel {
namespace {

// v_l += factor * L(v)_l for the inner points, all from the values before the step. The radius
// step is weighted by radius_weight() of the point.
void umbrella_step(std::vector<CenterlinePoint>& points, const std::vector<double>& radius_weight, double factor) {
  CenterlinePoint previous = points.front();  // v_{l-1} before this step
  for (std::size_t l = 1; l + 1 < points.size(); ++l) {
    const CenterlinePoint current = points[l];
    const CenterlinePoint& next = points[l + 1];
    // Normal to the neighbours' chord only: the umbrella step of unevenly spaced points on a
    // straight line slides them along it, away from the radius they carry. (Non-finite or
    // overflowing values, from a point outside the body's range, are left to the mesher's range
    // check, so that a NaN stays in the coordinate it was in.)
    glm::dvec3 step = 0.5 * (previous.pos_mm + next.pos_mm) - current.pos_mm;
    const glm::dvec3 chord = next.pos_mm - previous.pos_mm;
    const double chord2 = glm::dot(chord, chord);
    const double along = glm::dot(step, chord);
    if (chord2 > 0.0 && std::isfinite(chord2) && std::isfinite(along)) step -= (along / chord2) * chord;
    points[l].pos_mm += factor * step;
    points[l].radius_mm +=
        factor * radius_weight[l] * (0.5 * (previous.radius_mm + next.radius_mm) - current.radius_mm);
    previous = current;
  }
}

}  // namespace

void smooth_polyline(std::vector<CenterlinePoint>& points) {
  if (points.size() < 3) return;
  CenterlinePoint previous = points.front();  // v_{l-1}, already filtered
  for (std::size_t l = 1; l + 1 < points.size(); ++l) {
    CenterlinePoint v;
    v.pos_mm = (previous.pos_mm + 2.0 * points[l].pos_mm + points[l + 1].pos_mm) * 0.25;
    v.radius_mm = (previous.radius_mm + 2.0 * points[l].radius_mm + points[l + 1].radius_mm) * 0.25;
    points[l] = v;
    previous = v;
  }
}

void taubin_polyline(std::vector<CenterlinePoint>& points) {
  if (points.size() < 3) return;
  // Radius: full weight where points are at most kRadiusSmoothingSpacing radii apart, falling
  // off with the square of the spacing beyond.
  std::vector<double> weight(points.size(), 0.0);
  for (std::size_t l = 1; l + 1 < points.size(); ++l) {
    const double h = 0.5 * (glm::length(points[l + 1].pos_mm - points[l].pos_mm) +
                            glm::length(points[l].pos_mm - points[l - 1].pos_mm));
    const double q = h > 0.0 ? kRadiusSmoothingSpacing * points[l].radius_mm / h : 1.0;
    weight[l] = std::min(1.0, q * q);
  }
  umbrella_step(points, weight, kTaubinLambda);
  umbrella_step(points, weight, kTaubinMu);
}

VesselModel smooth_centerlines(const VesselModel& model, const VesselGraph& graph, int passes, bool snap_junctions,
                               SmoothingMethod method) {
  VesselModel out = model;
  for (std::size_t j = 0; snap_junctions && j < graph.junctions().size(); ++j) {
    const Junction& junction = graph.junctions()[j];
    for (const SegmentEnd& e : junction.ends) {
      auto& points = out.segments[e.segment].points;
      if (points.empty()) continue;
      (e.at_end ? points.back() : points.front()).pos_mm = junction.center_mm;
    }
  }
  for (Segment& s : out.segments) {
    for (int pass = 0; pass < passes; ++pass) {
      if (method == SmoothingMethod::kTaubin) taubin_polyline(s.points);
      else smooth_polyline(s.points);
    }
  }
  return out;
}

}  // namespace cathbox::vessel

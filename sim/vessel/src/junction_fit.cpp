#include "junction_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "centerline_polyline.hpp"

namespace cathbox::vessel::detail {
namespace {

constexpr double kAxisReachRadii = 2.0;  // a branch's axis is kept this far beyond its ring
constexpr double kAxisStepRadii = 0.25;  // axis sample spacing, in radii

// The part of one branch's axis near the junction, from the junction end outward, sampled
// every `step` mm, with the branch's ring there.
struct Axis {
  std::vector<glm::dvec3> pos;
  std::vector<double> radius;
  double step = 0.0;
  double trim = 0.0;        // arc of the branch's ring from the junction end
  glm::dvec3 ring_center{0.0};
  double ring_radius = 0.0;
  std::int32_t segment_id = 0;
};

struct Nearest {
  double signed_distance = std::numeric_limits<double>::infinity();  // to the tube (< 0 inside)
  glm::dvec3 direction{0.0};                                          // from the axis to the point
  double radius = 0.0;
  double arc = 0.0;  // of the foot, from the junction end
};

[[nodiscard]] Nearest nearest_on(const Axis& axis, const glm::dvec3& p) {
  Nearest best;
  double best_d2 = std::numeric_limits<double>::infinity();
  glm::dvec3 best_foot(0.0);
  for (std::size_t i = 0; i + 1 < axis.pos.size(); ++i) {
    const glm::dvec3 a = axis.pos[i];
    const glm::dvec3 d = axis.pos[i + 1] - a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec3 foot = a + t * d;
    const double d2 = glm::dot(p - foot, p - foot);
    if (d2 < best_d2) {
      best_d2 = d2;
      best_foot = foot;
      best.radius = axis.radius[i] + t * (axis.radius[i + 1] - axis.radius[i]);
      best.arc = axis.step * (static_cast<double>(i) + t);
    }
  }
  const double dist = std::sqrt(best_d2);
  if (dist > 0.0) best.direction = (p - best_foot) / dist;
  best.signed_distance = dist - best.radius;
  return best;
}

[[nodiscard]] double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// The axes of a junction's branches; empty when no ring is further out than kFitTrimRadii.
[[nodiscard]] std::vector<Axis> junction_axes(const Junction& junction, const VesselModel& smoothed,
                                              const ControlMesh& control) {
  bool long_patch = false;
  std::vector<Axis> axes;
  for (const SegmentEnd& e : junction.ends) {
    const Polyline pl = make_polyline(smoothed.segments[e.segment]);
    if (pl.pos.size() < 2 || !(pl.length > 0.0)) return {};
    const std::uint32_t ring_index =
        e.at_end ? control.segment_first_ring[e.segment + 1] - 1 : control.segment_first_ring[e.segment];
    const Ring& ring = control.rings[ring_index];
    Axis axis;
    axis.trim = e.at_end ? pl.length - ring.arc_mm : ring.arc_mm;
    axis.ring_center = ring.center_mm;
    axis.ring_radius = ring.radius_mm;
    axis.segment_id = smoothed.segments[e.segment].id;
    long_patch = long_patch || axis.trim > kFitTrimRadii * ring.radius_mm;
    const double reach = std::min(pl.length, axis.trim + kAxisReachRadii * ring.radius_mm);
    const int steps = std::clamp(static_cast<int>(std::ceil(reach / (kAxisStepRadii * ring.radius_mm))), 1, 256);
    axis.step = reach / steps;
    for (int k = 0; k <= steps; ++k) {
      const double from_end = axis.step * k;
      const Sample s = sample(pl, e.at_end ? pl.length - from_end : from_end);
      axis.pos.push_back(s.pos);
      axis.radius.push_back(s.radius);
    }
    axes.push_back(std::move(axis));
  }
  if (!long_patch) return {};
  return axes;
}

}  // namespace

JunctionFitReport fit_junction_patches(SurfaceMesh& mesh, const VesselModel& smoothed, const VesselGraph& graph,
                                       const ControlMesh& control) {
  JunctionFitReport report;
  const auto& junctions = graph.junctions();
  std::vector<std::vector<Axis>> axes(junctions.size());
  // Per HCLM segment id: the fitted (junction, branch) pairs it takes part in.
  std::unordered_map<std::int32_t, std::vector<std::pair<int, int>>> fitted_segments;
  for (std::size_t j = 0; j < junctions.size(); ++j) {
    axes[j] = junction_axes(junctions[j], smoothed, control);
    for (std::size_t b = 0; b < axes[j].size(); ++b) {
      fitted_segments[axes[j][b].segment_id].emplace_back(static_cast<int>(j), static_cast<int>(b));
    }
  }
  if (fitted_segments.empty()) return report;

  // The vertices to fit: those of the fitted junctions' triangles (a vertex on a patch's ring
  // edge is shared with the tube), and the tube's vertices within kFitTubeFadeRadii beyond the
  // ring (branch >= 0), where the move fades out.
  constexpr int kPatch = -1;
  std::vector<int> owner(mesh.vertex_count(), -1);
  std::vector<int> branch(mesh.vertex_count(), kPatch);
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const FaceRegion region = mesh.triangle_regions[f];
    if (region.kind != RegionKind::kJunction || axes[static_cast<std::size_t>(region.id)].empty()) continue;
    for (std::size_t k = 0; k < 3; ++k) owner[mesh.triangles[3 * f + k]] = region.id;
  }
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const FaceRegion region = mesh.triangle_regions[f];
    if (region.kind != RegionKind::kSegment) continue;
    const auto it = fitted_segments.find(region.id);
    if (it == fitted_segments.end()) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[3 * f + k];
      if (owner[v] >= 0) continue;
      for (const auto& [j, b] : it->second) {
        const Axis& axis = axes[static_cast<std::size_t>(j)][static_cast<std::size_t>(b)];
        const double reach = (kFitTubeFadeRadii + 2.0) * axis.ring_radius;
        if (glm::length(glm::dvec3(mesh.positions_mm[v]) - axis.ring_center) > reach) continue;
        owner[v] = j;
        branch[v] = b;
        break;
      }
    }
  }
  std::vector<char> fitted(junctions.size(), 0);
  for (std::size_t v = 0; v < owner.size(); ++v) {
    if (owner[v] < 0) continue;
    const std::vector<Axis>& branch_axes = axes[static_cast<std::size_t>(owner[v])];
    const glm::dvec3 p(mesh.positions_mm[v]);
    Nearest first, second;
    for (const Axis& axis : branch_axes) {
      const Nearest n = nearest_on(axis, p);
      if (n.signed_distance < first.signed_distance) {
        second = first;
        first = n;
      } else if (n.signed_distance < second.signed_distance) {
        second = n;
      }
    }
    if (!(first.radius > 0.0) || glm::dot(first.direction, first.direction) == 0.0) continue;
    // Fitted where one tube is clearly nearest, or where the two nearest tubes lie the same way
    // (above both of two branches running side by side); left where they lie opposite (the
    // crotch, the bridge between branches that have parted) and where the surface is far from
    // every tube (the hull's bridge between parted branches, which no tube explains).
    const double side = std::max(smoothstep((second.signed_distance - first.signed_distance) / (kFitBlendRadii * first.radius)),
                                 smoothstep((glm::dot(first.direction, second.direction) - kFitSameSide) / (1.0 - kFitSameSide)));
    const double near = 1.0 - smoothstep((std::abs(first.signed_distance) - kFitFullRadii * first.radius) /
                                         ((kFitMaxMoveRadii - kFitFullRadii) * first.radius));
    double w = side * near;
    if (branch[v] != kPatch) {
      const Axis& own = branch_axes[static_cast<std::size_t>(branch[v])];
      const Nearest on_own = nearest_on(own, p);
      w *= 1.0 - smoothstep((on_own.arc - own.trim) / (kFitTubeFadeRadii * own.ring_radius));
    }
    if (w <= 0.0) continue;
    const double move = -w * first.signed_distance;
    mesh.positions_mm[v] = glm::vec3(p + move * first.direction);
    ++report.vertices;
    report.max_move_mm = std::max(report.max_move_mm, std::abs(move));
    fitted[static_cast<std::size_t>(owner[v])] = 1;
  }
  // The fitted vertices' normals from their (moved) triangles, area weighted: every triangle
  // touching one of them.
  std::vector<glm::dvec3> sum(owner.size(), glm::dvec3(0.0));
  for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
    const std::uint32_t* t = &mesh.triangles[3 * f];
    if (owner[t[0]] < 0 && owner[t[1]] < 0 && owner[t[2]] < 0) continue;
    const glm::dvec3 a(mesh.positions_mm[t[0]]);
    const glm::dvec3 n = glm::cross(glm::dvec3(mesh.positions_mm[t[1]]) - a, glm::dvec3(mesh.positions_mm[t[2]]) - a);
    for (int k = 0; k < 3; ++k) sum[t[k]] += n;
  }
  for (std::size_t v = 0; v < owner.size(); ++v) {
    if (owner[v] >= 0 && glm::dot(sum[v], sum[v]) > 0.0) mesh.normals[v] = glm::vec3(glm::normalize(sum[v]));
  }
  report.junctions = static_cast<std::size_t>(std::count(fitted.begin(), fitted.end(), 1));
  return report;
}

}  // namespace cathbox::vessel::detail

// The control mesh: rings along each smoothed segment, junction patches and end caps
// (thesis 3.2.3). Here the run and each junction's trims; the rings and their frames are in
// control_mesh_rings.cpp, the vertices and faces in control_mesh_faces.cpp.
#include "vessel/control_mesh_builder.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>

#include <glm/geometric.hpp>

#include "control_mesh_steps.hpp"
#include "vessel/point_range.hpp"

namespace cathbox::vessel {
namespace detail {
namespace {

constexpr double kInitialTrimRadii = 1.0;   // first guess of a junction ring's distance, in radii
constexpr double kTrimStepRadii = 0.2;      // step when rings still overlap
constexpr double kPlaneMarginRadii = 0.15;  // how far behind another ring's plane a ring must be

}  // namespace

ControlMeshResult ControlMeshBuilder::run() {
  if (m_ < 3 || m_ > 256) return base::Error{"ring size must be between 3 and 256, got " + std::to_string(m_)};
  if (options_.smoothing_passes < 0) return base::Error{"smoothing passes must be >= 0"};
  ratio_ = options_.compensate_shrink ? tube_shrink_ratio(m_) : 1.0;
  for (const Segment& s : model_.segments) {
    // Every later cast and count assumes finite, physical numbers: a model that did not come
    // through a reader (which checks them) is refused here, never meshed into undefined values.
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      if (std::string problem = point_range_problem(s.points[k].pos_mm, s.points[k].radius_mm); !problem.empty()) {
        return base::Error{"segment " + std::to_string(s.id) + " point " + std::to_string(k) + ": " + problem};
      }
    }
    polylines_.push_back(make_polyline(s));
    if (s.points.size() < 2 || !(polylines_.back().length > 0.0)) {
      return base::Error{"segment " + std::to_string(s.id) + " has zero length"};
    }
  }
  trims_.assign(2 * model_.segments.size(), 0.0);
  if (options_.trim_at_junctions) compute_trims();
  reserve_mesh();
  place_rings();
  propagate_frames();
  emit_vertices();
  emit_tubes();
  if (options_.caps) emit_caps();
  if (std::string e = emit_junctions(); !e.empty()) return base::Error{std::move(e)};
  return ControlMeshResult(std::move(mesh_));
}

[[nodiscard]] double ControlMeshBuilder::end_arc(const SegmentEnd& e, double trim) const {
  return e.at_end ? polylines_[e.segment].length - trim : trim;
}

void ControlMeshBuilder::compute_trims() {
  std::vector<char> settled(graph_.junctions().size(), 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t j = 0; j < graph_.junctions().size(); ++j) {
      if (!settled[j]) settled[j] = trim_junction(graph_.junctions()[j], pass == 1) ? 1 : 0;
    }
  }
}

bool ControlMeshBuilder::trim_junction(const Junction& junction, bool relaxed) {
  const std::size_t k = junction.ends.size();
  std::vector<double> d(k);
  std::vector<double> max_d(k);
  for (std::size_t i = 0; i < k; ++i) {
    max_d[i] = trim_limit(junction, junction.ends[i], relaxed);
    const SegmentEnd& e = junction.ends[i];
    const double r = sample(polylines_[e.segment], end_arc(e, 0.0)).radius / ratio_;
    d[i] = std::min(std::max(kInitialTrimRadii * r, trims_[2 * e.segment + (e.at_end ? 1 : 0)]), max_d[i]);
  }
  std::vector<Sample> at(k);
  std::vector<glm::dvec3> out_normal(k);
  bool clear = false;
  for (int iteration = 0; iteration < 400 && !clear; ++iteration) {
    for (std::size_t i = 0; i < k; ++i) {
      const SegmentEnd& e = junction.ends[i];
      at[i] = sample(polylines_[e.segment], end_arc(e, d[i]));
      out_normal[i] = e.at_end ? -at[i].tangent : at[i].tangent;
    }
    clear = true;
    bool changed = false;
    for (std::size_t i = 0; i < k; ++i) {
      if (!ring_in_front(at, out_normal, i)) continue;
      // A ring reaches in front of ring i's plane: move ring i further out.
      clear = false;
      if (d[i] < max_d[i]) {
        d[i] = std::min(max_d[i], d[i] + kTrimStepRadii * at[i].radius / ratio_);
        changed = true;
      }
    }
    if (!changed) break;
  }
  for (std::size_t i = 0; i < k; ++i) {
    const SegmentEnd& e = junction.ends[i];
    trims_[2 * e.segment + (e.at_end ? 1 : 0)] = d[i];
  }
  return clear;
}

[[nodiscard]] double ControlMeshBuilder::trim_limit(const Junction& junction, const SegmentEnd& e, bool relaxed) const {
  const Polyline& pl = polylines_[e.segment];
  const int other_junction = graph_.junction_of(e.segment, !e.at_end);
  const double other_trim = trims_[2 * e.segment + (e.at_end ? 0 : 1)];
  const bool same_junction = other_junction >= 0 && &graph_.junctions()[static_cast<std::size_t>(other_junction)] == &junction;
  if (relaxed && !same_junction) return std::max(0.0, 0.95 * pl.length - other_trim);
  return (other_junction >= 0 ? 0.47 : 0.85) * pl.length;
}

[[nodiscard]] bool ControlMeshBuilder::ring_in_front(const std::vector<Sample>& at, const std::vector<glm::dvec3>& out_normal, std::size_t i) const {
  for (std::size_t j = 0; j < at.size(); ++j) {
    if (i == j) continue;
    const double cos_ij = glm::dot(out_normal[i], at[j].tangent);
    const double reach = glm::dot(out_normal[i], at[j].pos - at[i].pos) +
                         at[j].radius / ratio_ * std::sqrt(std::max(0.0, 1.0 - cos_ij * cos_ij));
    if (!(reach <= -kPlaneMarginRadii * at[i].radius / ratio_)) return true;  // (NaN counts as in front)
  }
  return false;
}

}  // namespace detail


double tube_shrink_ratio(int ring_points) {
  const double phi = 2.0 * std::numbers::pi / ring_points;
  // Uniform cubic B-spline through the regular M-gon: at a vertex (P- + 4P + P+)/6, between
  // two vertices (P-1 + 23 P0 + 23 P1 + P2)/48 (radial parts).
  const double at_vertex = (4.0 + 2.0 * std::cos(phi)) / 6.0;
  const double between = (std::cos(1.5 * phi) + 23.0 * std::cos(0.5 * phi)) / 24.0;
  return 0.5 * (at_vertex + between);
}

std::string fallback_summary(const ControlMesh& mesh) {
  const std::size_t n = mesh.fallback_junctions.size();
  if (n == 0) return {};
  std::string out = std::to_string(n) + (n == 1 ? " junction" : " junctions") + " meshed by the spherical-hull fallback: ";
  for (std::size_t i = 0; i < n; ++i) out += (i > 0 ? "; " : "") + mesh.fallback_junctions[i].what;
  return out;
}

ControlMeshResult build_control_mesh(const VesselModel& smoothed, const VesselGraph& graph, const MeshOptions& options) {
  return detail::ControlMeshBuilder(smoothed, graph, options).run();
}

}  // namespace cathbox::vessel

#include "tool/lumen_remodel.hpp"
#include "tool/wall_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {

constexpr double kReferenceNear_mm = 5.0;  // the reference window starts this far from the point ...
constexpr double kReferenceFar_mm = 10.0;  // ... and ends here, on each side
constexpr double kLesionNarrowing = 0.9;   // lesion points are narrower than this x reference
constexpr double kMinLesion = 0.1;         // less narrowing than this is no lesion

// Arc length of each point of a segment from its first point.
std::vector<double> arcs(const vessel::Segment& s) {
  std::vector<double> a(s.points.size(), 0.0);
  for (std::size_t i = 1; i < s.points.size(); ++i) a[i] = a[i - 1] + glm::length(s.points[i].pos_mm - s.points[i - 1].pos_mm);
  return a;
}

// Closest point of a segment's centre line to p: (squared distance, arc length there).
std::pair<double, double> project(const vessel::Segment& s, const std::vector<double>& arc, const glm::dvec3& p) {
  const CentrelineFoot f = nearest_on_centreline(s, p);
  if (s.points.size() < 2) return {f.distance2_mm2, 0.0};
  return {f.distance2_mm2, arc[f.piece] + f.t * (arc[f.piece + 1] - arc[f.piece])};
}

// Middle of a polyline by arc length.
glm::dvec3 middle(std::span<const glm::dvec3> axis) {
  double total = 0.0;
  for (std::size_t i = 1; i < axis.size(); ++i) total += glm::length(axis[i] - axis[i - 1]);
  double want = 0.5 * total;
  for (std::size_t i = 1; i < axis.size(); ++i) {
    const double len = glm::length(axis[i] - axis[i - 1]);
    if (want <= len && len > 0.0) return axis[i - 1] + (axis[i] - axis[i - 1]) * (want / len);
    want -= len;
  }
  return axis.back();
}

// The healthy vessel on each side of point i: the widest point 5-10 mm proximal and the widest
// 5-10 mm distal along the segment (radius 0: the segment does not reach that window).
struct ReferenceWindows {
  double proximal_r = 0.0, proximal_arc = 0.0, distal_r = 0.0, distal_arc = 0.0;
};
ReferenceWindows reference_windows(const vessel::Segment& s, const std::vector<double>& arc, std::size_t i) {
  ReferenceWindows w;
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    const double d = arc[k] - arc[i];
    const double r = s.points[k].radius_mm;
    if (d <= -kReferenceNear_mm && d >= -kReferenceFar_mm && r > w.proximal_r) {
      w.proximal_r = r;
      w.proximal_arc = arc[k];
    }
    if (d >= kReferenceNear_mm && d <= kReferenceFar_mm && r > w.distal_r) {
      w.distal_r = r;
      w.distal_arc = arc[k];
    }
  }
  return w;
}

// The line through the two windows' widest points, read at point i (0 without both).
double interpolated(const ReferenceWindows& w, double arc_i) {
  if (!(w.proximal_r > 0.0 && w.distal_r > 0.0)) return 0.0;
  return w.proximal_r + (w.distal_r - w.proximal_r) * (arc_i - w.proximal_arc) / (w.distal_arc - w.proximal_arc);
}

}  // namespace

double reference_radius(const vessel::Segment& s, std::size_t i) {
  const std::vector<double> arc = arcs(s);
  return interpolated(reference_windows(s, arc, i), arc[i]);
}

double sizing_reference_radius(const vessel::Segment& s, std::size_t i) {
  const std::vector<double> arc = arcs(s);
  const ReferenceWindows w = reference_windows(s, arc, i);
  const double both = interpolated(w, arc[i]);
  if (both > 0.0) return both;
  if (w.proximal_r > 0.0 || w.distal_r > 0.0) return std::max(w.proximal_r, w.distal_r);
  return s.points[i].radius_mm;
}

Lesion find_lesion(const vessel::VesselModel& model) {
  Lesion lesion;
  double worst = kMinLesion;
  for (std::size_t s = 0; s < model.segments.size(); ++s) {
    const vessel::Segment& seg = model.segments[s];
    for (std::size_t i = 0; i < seg.points.size(); ++i) {
      const double ref = reference_radius(seg, i);
      if (!(ref > 0.0)) continue;  // no healthy vessel on both sides: not gradable
      const double narrowing = 1.0 - seg.points[i].radius_mm / ref;
      if (narrowing > worst) {
        worst = narrowing;
        lesion.segment = s;
        lesion.worst = i;
        lesion.reference_diameter_mm = 2.0 * ref;
      }
    }
  }
  if (!lesion.found()) return lesion;
  const vessel::Segment& seg = model.segments[lesion.segment];
  const auto narrowed = [&](std::size_t i) { return seg.points[i].radius_mm < kLesionNarrowing * reference_radius(seg, i); };
  lesion.first = lesion.last = lesion.worst;
  while (lesion.first > 0 && narrowed(lesion.first - 1)) --lesion.first;
  while (lesion.last + 1 < seg.points.size() && narrowed(lesion.last + 1)) ++lesion.last;
  return lesion;
}

double stenosis_percent(const vessel::VesselModel& model, const Lesion& lesion) {
  if (!lesion.found() || lesion.segment >= model.segments.size()) return 0.0;
  const vessel::Segment& seg = model.segments[lesion.segment];
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = lesion.first; i <= lesion.last && i < seg.points.size(); ++i) {
    smallest = std::min(smallest, seg.points[i].radius_mm);
  }
  return std::max(0.0, 100.0 * (1.0 - 2.0 * smallest / lesion.reference_diameter_mm));
}

LumenRemodel::LumenRemodel(vessel::VesselModel source, const LumenRemodelParams& params)
    : model_(std::move(source)), params_(params) {
  params_.recoil = std::clamp(params_.recoil, 0.0, 1.0);
  for (const vessel::Segment& s : model_.segments) {
    std::vector<double> r;
    for (const vessel::CenterlinePoint& p : s.points) r.push_back(p.radius_mm);
    r0_.push_back(r);
    arc_.push_back(arcs(s));
    std::vector<double> ref;
    for (std::size_t i = 0; i < s.points.size(); ++i) ref.push_back(sizing_reference_radius(s, i));
    ref0_.push_back(ref);
  }
  peak_ = r0_;
  taken_ = r0_;
  lesion_ = find_lesion(model_);
  before_percent_ = stenosis_percent();
}

LumenRemodel::Span LumenRemodel::covered(std::span<const glm::dvec3> axis) const {
  Span span;
  if (axis.size() < 2 || model_.segments.empty()) return span;
  // The segment holding the balloon's middle, then the points between its two ends there.
  const glm::dvec3 mid = middle(axis);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s < model_.segments.size(); ++s) {
    if (model_.segments[s].points.empty()) continue;
    const double d2 = project(model_.segments[s], arc_[s], mid).first;
    if (d2 < best) {
      best = d2;
      span.segment = s;
    }
  }
  const vessel::Segment& seg = model_.segments[span.segment];
  const std::vector<double>& arc = arc_[span.segment];
  const double a = project(seg, arc, axis.front()).second;
  const double b = project(seg, arc, axis.back()).second;
  const double lo = std::min(a, b), hi = std::max(a, b);
  bool any = false;
  for (std::size_t i = 0; i < arc.size(); ++i) {
    if (arc[i] < lo || arc[i] > hi) continue;
    if (!any) span.first = i;
    any = true;
    span.last = i;
  }
  if (!any) {  // a balloon shorter than the point spacing: its nearest point
    const double m = project(seg, arc, mid).second;
    std::size_t near = 0;
    for (std::size_t i = 1; i < arc.size(); ++i) {
      if (std::abs(arc[i] - m) < std::abs(arc[near] - m)) near = i;
    }
    span.first = span.last = near;
  }
  return span;
}

void LumenRemodel::set_radius(std::size_t s, std::size_t i, double r) { model_.segments[s].points[i].radius_mm = r; }

bool LumenRemodel::apply(const BalloonPose& balloon) {
  const bool inflated = balloon.inflated && balloon.diameter_mm > 0.0 && balloon.axis_mm.size() >= 2;
  if (!inflated) over_ = false;
  if (!inflated && !pressing_) return false;
  const auto recoiled = [&](std::size_t s, std::size_t i) {
    return r0_[s][i] + (1.0 - params_.recoil) * (peak_[s][i] - r0_[s][i]);
  };
  bool changed = false;
  const auto relax = [&](const Span& sp) {
    for (std::size_t i = sp.first; i <= sp.last; ++i) {
      set_radius(sp.segment, i, recoiled(sp.segment, i));
      changed |= std::abs(model_.segments[sp.segment].points[i].radius_mm - taken_[sp.segment][i]) > params_.min_change_mm;
    }
  };
  Span span = inflated ? covered(balloon.axis_mm) : Span{};
  if (pressing_ && inflated && span.segment == last_span_.segment) {
    // One inflation presses every point it has covered (a gripping balloon hardly moves; a
    // node jittering across a span end would otherwise let a point recoil and come back).
    span.first = std::min(span.first, last_span_.first);
    span.last = std::max(span.last, last_span_.last);
  } else if (pressing_) {
    relax(last_span_);
  }
  pressing_ = inflated;
  if (!inflated) return changed;
  last_span_ = span;
  const double rb = 0.5 * balloon.diameter_mm;
  for (std::size_t i = span.first; i <= span.last; ++i) {
    peak_[span.segment][i] = std::max(peak_[span.segment][i], rb);
    set_radius(span.segment, i, std::max(recoiled(span.segment, i), rb));
    changed |= std::abs(model_.segments[span.segment].points[i].radius_mm - taken_[span.segment][i]) > params_.min_change_mm;
  }
  // Over-sizing: the balloon against the healthy vessel's reference where it sits (QCA
  // reference from the original radii).
  const double ref = 2.0 * ref0_[span.segment][(span.first + span.last) / 2];
  const double ratio = ref > 0.0 ? balloon.diameter_mm / ref : 0.0;
  max_ratio_ = std::max(max_ratio_, ratio);
  if (ratio > params_.oversize_ratio && !over_) {
    over_ = true;
    ++rupture_events_;
  }
  return changed;
}

const vessel::VesselModel& LumenRemodel::take_model() {
  for (std::size_t s = 0; s < model_.segments.size(); ++s) {
    for (std::size_t i = 0; i < model_.segments[s].points.size(); ++i) taken_[s][i] = model_.segments[s].points[i].radius_mm;
  }
  return model_;
}

}  // namespace cathbox::tool

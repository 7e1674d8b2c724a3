// The rod's material along its length: each node's radius, bending and torsion stiffness, rest
// shape (pre-curve, coil) and drag from the section holding it; the stiffness a coaxial inner
// tool adds; the look-ups by distance from the tip; and the step's stiffness and drag weights.
#include <algorithm>
#include <cmath>
#include <vector>

#include "base/portable_math.hpp"
#include "rod_geometry.hpp"
#include "tool/coil_shape.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

using rod_detail::kMilli;
using rod_detail::station_near;

// The section holding node k.
const ToolSection& Rod::section_at(std::size_t k) const {
  double from_proximal = length_mm_ - from_tip_[k];
  for (const ToolSection& candidate : spec_.sections) {
    if (from_proximal <= candidate.length_mm) return candidate;
    from_proximal -= candidate.length_mm;
  }
  return spec_.sections.back();
}

void Rod::set_node_material(std::size_t k) {
  const std::size_t n = from_tip_.size();
  const double left = k > 0 ? rest_[k - 1] : 0.0;
  const double right = k + 1 < n ? rest_[k] : 0.0;
  voronoi_[k] = 0.5 * (left + right);
  const ToolSection* sec = &section_at(k);
  radius_[k] = 0.5 * sec->outer_diameter_mm;
  inner_radius_[k] = 0.5 * spec_.inner_diameter_mm;
  // A coil's joint with its pusher bends as its sections in series (vertex_bending_Nmm2); other
  // tools keep the section holding the node (the stent retriever's pull was tuned on that).
  ei_[k] = (spec_.kind == ToolKind::kCoil
                ? vertex_bending_Nmm2(length_mm_ - from_tip_[k] - 0.5 * right, length_mm_ - from_tip_[k] + 0.5 * left,
                                      sec->bending_stiffness_Nmm2)
                : sec->bending_stiffness_Nmm2) *
           kMilli;
  gj_[k] = sec->torsion_stiffness_Nmm2 * kMilli;
  if (k > 0 && k + 1 < n) {
    const CoilRest rest = coil_rest(*sec, from_tip_[k]);
    if (rest.curvature_per_mm != 0.0) {
      set_rest_shape(k, rest.curvature_per_mm, rest.direction_rad);
    } else if (sec->curve_deg != 0.0 && sec->length_mm > 0.0) {
      set_rest_shape(k, sec->curve_deg * (M_PI / 180.0) / sec->length_mm, 0.0);
    }
  }
  drag_per_mm_[k] = spec_.drag_at(radius_[k]);
}

namespace {
// f(section, overlap) for each section overlapping [lo, hi] (mm from the proximal end), in order.
template <class F>
void for_each_section_overlap(const std::vector<ToolSection>& sections, double lo, double hi, F&& f) {
  double start = 0.0;
  for (const ToolSection& sec : sections) {
    const double end = start + sec.length_mm;
    const double overlap = std::min(end, hi) - std::max(start, lo);
    if (overlap > 0.0) f(sec, overlap);
    start = end;
  }
}
}  // namespace

// A vertex's bending stiffness over its Voronoi region [from, to] (from the proximal end): the
// sections' compliances in series, l / sum(l_i / EI_i). A vertex on a section boundary bends
// mostly in its softer half; taking the proximal section's EI made the joint of a coil (0.02
// N mm^2) and its pusher (10) as stiff as the pusher, so a coil's last node leaving the
// microcatheter was held on the catheter's tip line by the pusher's hinge, into the sac wall.
double Rod::vertex_bending_Nmm2(double from_mm, double to_mm, double fallback_Nmm2) const {
  if (!(to_mm > from_mm)) return fallback_Nmm2;
  double covered = 0.0, compliance = 0.0;
  bool unbendable = false;
  for_each_section_overlap(spec_.sections, from_mm, to_mm, [&](const ToolSection& sec, double overlap) {
    if (unbendable || !(sec.bending_stiffness_Nmm2 > 0.0)) {
      unbendable = true;
      return;
    }
    covered += overlap;
    compliance += overlap / sec.bending_stiffness_Nmm2;
  });
  if (unbendable) return fallback_Nmm2;
  return compliance > 0.0 ? covered / compliance : fallback_Nmm2;
}

double Rod::bending_integral_Nmm3(double near_mm, double far_mm) const {
  // Sections run from the proximal end: station s from the tip is length - s from there.
  // (A pusher whose coil was released keeps the coil's section past its new tip: cut there.)
  const double lo = std::max(0.0, length_mm_ - std::max(near_mm, far_mm));
  const double hi = std::min(length_mm_, length_mm_ - std::min(near_mm, far_mm));
  double sum = 0.0;
  for_each_section_overlap(spec_.sections, lo, hi,
                           [&](const ToolSection& sec, double overlap) { sum += overlap * sec.bending_stiffness_Nmm2; });
  return sum;
}

void Rod::set_rest_shape(std::size_t k, double curvature_per_mm, double direction_rad) {
  const double phi = std::clamp(curvature_per_mm * voronoi_[k], -3.0, 3.0);
  const double bar = 2.0 * base::portable::tan(0.5 * phi);
  const double turn = 2.0 * base::portable::sin(0.5 * phi);
  const double c = base::portable::cos(direction_rad);
  const double s = base::portable::sin(direction_rad);
  kbar1_[k] = bar * c;
  kbar2_[k] = bar * s;
  kturn1_[k] = turn * c;
  kturn2_[k] = turn * s;
}

double Rod::rest_curvature_per_mm(std::size_t k) const {
  if (k >= kturn1_.size() || voronoi_[k] <= 0.0) return 0.0;
  const double turn = std::sqrt(kturn1_[k] * kturn1_[k] + kturn2_[k] * kturn2_[k]);
  return 2.0 * base::portable::asin(std::min(1.0, 0.5 * turn)) / voronoi_[k];
}

void Rod::set_extra_bending(std::size_t first, std::span<const double> ei_Nmm2) {
  const std::size_t size = ei_extra_.size();
  const std::size_t begin = std::min(first, size);
  const std::size_t end = std::min(size, begin + ei_Nmm2.size());
  for (std::size_t k = extra_set_.begin_in(size); k < extra_set_.end_in(size); ++k) {
    if (k < begin || k >= end) ei_extra_[k] = 0.0;
  }
  extra_set_.clear();
  for (std::size_t k = begin; k < end; ++k) {
    ei_extra_[k] = std::max(0.0, ei_Nmm2[k - begin]) * kMilli;
    extra_set_.add(k);
  }
}

double Rod::radius_at_mm(double from_tip_mm, std::size_t& station) const {
  return radius_[station_near(from_tip_, from_tip_mm, station)];
}
double Rod::bending_at_Nmm2(double from_tip_mm, std::size_t& station) const {
  return ei_[station_near(from_tip_, from_tip_mm, station)] / kMilli;
}
double Rod::inner_radius_at_mm(double from_tip_mm, std::size_t& station) const {
  return inner_radius_[station_near(from_tip_, from_tip_mm, station)];
}

// One look-up each: a walk that starts with a search.
double Rod::radius_at_mm(double from_tip_mm) const {
  std::size_t station = kNoStation;
  return radius_at_mm(from_tip_mm, station);
}
double Rod::bending_at_Nmm2(double from_tip_mm) const {
  std::size_t station = kNoStation;
  return bending_at_Nmm2(from_tip_mm, station);
}
double Rod::inner_radius_at_mm(double from_tip_mm) const {
  std::size_t station = kNoStation;
  return inner_radius_at_mm(from_tip_mm, station);
}

void Rod::update_weights(double dt_s) {
  // What the assembly and the line search would otherwise divide for at every call.
  const std::size_t n = x_.size();
  const double ea = spec_.axial_stiffness_N * kMilli;
  for (std::size_t k = first_; k + 1 < n; ++k) axial_k_[k] = ea / rest_[k];
  // At the clamp vertex only the half edge past it bends (the clamp sits at the vertex). The
  // first free node bends over its distal half edge plus as much of its proximal half edge as
  // it is past the entry, halved: a node that has just crossed the entry (the clamp vertex a
  // tick ago) keeps the clamp vertex's half edge, and one a whole edge past it has its Voronoi
  // region. A first free node bending over its whole region at once halved the stiffness of
  // the node that crossed, at every node the tool slid by (the hand force of a coil pushed out
  // of its microcatheter, or a wire drawn back into it, a sawtooth of one node spacing).
  // With the clamp's hinge at the entry point (clamp_shift_mm_) the clamp edge bends over the
  // part past the entry: the clamp vertex over half of it, and the two vertices' rest turns are
  // scaled to the lengths they bend over (2 sin(phi / 2) to first order in phi).
  const double past = free_ ? 0.0 : insertion_mm_ - from_tip_[std::min(first_free_, n - 1)];
  // While a drawn-back tool's hinge walks to the entry (update_window) the clamp vertex bends over
  // the half edge past its hinge and the rest keep the clamp node's weights: the hinge's at a
  // shift just over 0 would add the part of the edge behind the entry to the first free node's at
  // once (a cantilever's deflection stepped by 0.2 of an edge's hinge as the walk began).
  const bool hinge = !free_ && clamp_shift_mm_ > 0.0 && !hinge_walking_;
  hinge_turn_scale_[0] = hinge_turn_scale_[1] = 1.0;
  for (std::size_t i = first_ + 1; i + 1 < n; ++i) {
    double length = voronoi_[i];
    if (!free_ && i == first_ + 1) {
      length = 0.5 * (rest_[i] - clamp_shift_mm_);
      if (hinge) hinge_turn_scale_[0] = length / voronoi_[i];
    } else if (hinge && i == first_ + 2) {
      length = 0.5 * (rest_[i] + rest_[i - 1] - clamp_shift_mm_);
      hinge_turn_scale_[1] = length / voronoi_[i];
    } else if (!free_ && i == first_ + 2) {
      length = 0.5 * rest_[i] + 0.5 * std::clamp(past, 0.0, rest_[i - 1]);
    }
    bend_w_[i] = (ei_[i] + ei_extra_[i]) / length;
  }
  for (std::size_t k = first_free_; k < n; ++k) drag_k_[k] = solver_drag(k) / dt_s;
}

}  // namespace cathbox::tool

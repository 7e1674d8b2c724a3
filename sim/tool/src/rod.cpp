// The rod's construction, its simulated window, its boundary and coupling hooks and its
// queries. The step's phases live in rod_step.cpp and the files it names; sim/tool/README.md
// ("Source layout") lists which file holds which part of the solver.
#include "tool/rod.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "rod_geometry.hpp"
#include "rod_node_contact.hpp"
#include "rod_step_start.hpp"
#include "tool/banded_cholesky.hpp"

namespace cathbox::tool {

using rod_detail::finite_or;
using rod_detail::perpendicular_unit;
using rod_detail::station_at;

namespace {

// Material stations from the tip: fine over the tip zone, then growing to the largest spacing.
// A detachable coil ends at a station (its detachment zone).
std::vector<double> material_stations(const ToolSpec& spec, double length_mm) {
  const double h_tip = std::max(0.05, spec.tip_spacing_mm);
  const double h_max = std::max(h_tip, spec.max_spacing_mm);
  const double must = spec.detach_mm > 0.0 && spec.detach_mm < length_mm ? spec.detach_mm : -1.0;
  std::vector<double> s{0.0};
  for (;;) {
    const double u = s.back();
    const double ramp = std::clamp((u - spec.tip_zone_mm) / std::max(1e-9, 2.0 * spec.tip_zone_mm), 0.0, 1.0);
    const double h = h_tip + (h_max - h_tip) * ramp;
    if (must > u && must <= u + h) {
      if (must - u < 0.3 * h && u > 0.0) s.back() = must; else s.push_back(must);
      continue;
    }
    if (u + h >= length_mm - 0.3 * h) break;
    s.push_back(u + h);
  }
  s.push_back(length_mm);
  return s;
}

}  // namespace

Rod::Rod(const ToolSpec& spec, const RodSettings& settings) : spec_(spec), settings_(settings) {
  if (spec_.sections.empty()) spec_.sections.push_back(ToolSection{100.0});
  length_mm_ = spec_.length_mm();
  const std::vector<double> s = material_stations(spec_, length_mm_);
  const std::size_t n = s.size();
  from_tip_.resize(n);
  for (std::size_t k = 0; k < n; ++k) from_tip_[k] = s[n - 1 - k];

  radius_.resize(n);
  inner_radius_.resize(n);
  ei_.resize(n);
  ei_extra_.assign(n, 0.0);
  gj_.resize(n);
  kbar1_.assign(n, 0.0);
  kbar2_.assign(n, 0.0);
  kturn1_.assign(n, 0.0);
  kturn2_.assign(n, 0.0);
  voronoi_.resize(n);
  drag_per_mm_.resize(n);
  rest_.assign(n - 1, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) rest_[k] = from_tip_[k] - from_tip_[k + 1];
  for (std::size_t k = 0; k < n; ++k) set_node_material(k);
  size_state();
  size_scratch();
  set_entry(glm::dvec3(0.0), glm::dvec3(0, 0, 1));
}

Rod::Rod() = default;

void Rod::size_state() {
  const std::size_t n = from_tip_.size();
  x_.assign(n, glm::dvec3(0.0));
  x_start_.assign(n, glm::dvec3(0.0));
  x_pred_.assign(n, glm::dvec3(0.0));
  load_.assign(n, glm::dvec3(0.0));
  coupling_.assign(n, glm::dvec3(0.0));
  grip_anchor_.assign(n, glm::dvec3(0.0));
  grip_limit_.assign(n, 0.0);
  node_contacts_.assign(n, NodeContact{});
  theta_.assign(n - 1, 0.0);
  theta_start_.assign(n - 1, 0.0);
  ref_twist_.assign(n, 0.0);
  t_.assign(n - 1, glm::dvec3(0, 0, 1));
  d1_.assign(n - 1, glm::dvec3(1, 0, 0));
  m1_.assign(n - 1, glm::dvec3(1, 0, 0));
  m2_.assign(n - 1, glm::dvec3(0, 1, 0));
}

void Rod::size_scratch() {
  const std::size_t n = x_.size();
  grad_.assign(3 * n, 0.0);
  delta_.assign(3 * n, 0.0);
  work_.assign(3 * n, 0.0);
  plain_delta_.assign(3 * n, 0.0);
  predicted_.reserve(4 * n);
  friction_limit_.assign(n, 0.0);
  joined_.assign(n, 0);
  last_step_.assign(3 * n, 0.0);
  held_gap_.assign(n, 0.0);
  tw_diag_.assign(n, 0.0);
  tw_off_.assign(n, 0.0);
  tw_rhs_.assign(n, 0.0);
  tw_inv_.assign(n, 0.0);
  axial_k_.assign(n, 0.0);
  bend_w_.assign(n, 0.0);
  drag_k_.assign(n, 0.0);
  tw_regime_.assign(n, 0);
  contacts_.reserve(n);
  edge_contacts_.reserve(4 * n);
  gathered_at_.assign(n, glm::dvec3(0.0));
  solved_move_.assign(n, glm::dvec3(0.0));
  warm_ok_ = false;
  retired_work_ = solver_work();  // the replaced matrix's work is kept
  matrix_ = std::make_unique<BandedCholesky>(n);
}

Rod::SolverWork Rod::solver_work() const {
  SolverWork w = retired_work_;
  if (matrix_) {
    const BandedCholesky::Work& m = matrix_->work();
    w.factors += m.factors;
    w.rows_factored += m.rows_factored;
    w.solves += m.solves;
  }
  return w;
}

Rod::~Rod() = default;
Rod::Rod(Rod&&) noexcept = default;
Rod& Rod::operator=(Rod&&) noexcept = default;

double Rod::max_insertion_mm() const { return from_tip_.size() > 1 ? from_tip_[1] : 0.0; }

void Rod::set_entry(const glm::dvec3& point_mm, const glm::dvec3& direction) {
  entry_ = point_mm;
  const double len = glm::length(direction);
  dir_ = len > 1e-12 && std::isfinite(len) ? direction / len : glm::dvec3(0, 0, 1);
  entry_d1_ = perpendicular_unit(dir_);
  insertion_mm_ = 0.0;
  rotation_rad_ = 0.0;
  stepped_insertion_mm_ = 0.0;
  stepped_rotation_rad_ = 0.0;
  for (std::size_t k = 0; k < x_.size(); ++k) place_outside(k);
  for (NodeContact& c : node_contacts_) c = NodeContact{};
  contacts_.clear();
  hinged_back_at_kp_ = static_cast<std::size_t>(-1);
  update_window();
}

void Rod::set_boundary(double insertion_mm, double rotation_rad) {
  insertion_mm_ = std::clamp(finite_or(insertion_mm, 0.0), 0.0, max_insertion_mm());
  rotation_rad_ = finite_or(rotation_rad, rotation_rad_);
}

void Rod::set_node_load(std::size_t node, const glm::dvec3& force_mN) {
  if (node < load_.size()) load_[node] = force_mN;
}

void Rod::clear_node_loads() { std::fill(load_.begin(), load_.end(), glm::dvec3(0.0)); }

void Rod::add_coupling_load(std::size_t node, const glm::dvec3& force_mN) {
  if (node < coupling_.size() && std::isfinite(force_mN.x + force_mN.y + force_mN.z)) {
    coupling_[node] += force_mN;
    coupling_set_.add(node);
  }
}

void Rod::clear_coupling_loads() {
  const std::size_t size = coupling_.size();
  std::fill(coupling_.begin() + static_cast<std::ptrdiff_t>(coupling_set_.begin_in(size)),
            coupling_.begin() + static_cast<std::ptrdiff_t>(coupling_set_.end_in(size)), glm::dvec3(0.0));
  coupling_set_.clear();
}

void Rod::set_distal_friction(double length_mm, double mu) {
  distal_mu_ = mu > 0.0 ? mu : 0.0;
  distal_first_ = std::numeric_limits<std::size_t>::max();
  for (std::size_t k = 0; k < from_tip_.size(); ++k) {
    if (from_tip_[k] <= length_mm + 1e-9) {
      distal_first_ = k;
      break;
    }
  }
}

void Rod::set_contact_radius(std::size_t k, double radius_mm) {
  if (k >= radius_.size() || spec_.sections.empty()) return;
  const double own = 0.5 * section_at(k).outer_diameter_mm;  // radius_ holds what was set
  radius_[k] = radius_mm > own ? radius_mm : own;
}

void Rod::set_grip(std::size_t node, double limit_mN) {
  if (node >= grip_limit_.size()) return;
  const double limit = std::isfinite(limit_mN) ? std::max(0.0, limit_mN) : 0.0;
  if (limit > 0.0 && grip_limit_[node] <= 0.0) grip_anchor_[node] = x_[node];
  grip_limit_[node] = limit;
}

void Rod::forget_wall() {
  for (NodeContact& c : node_contacts_) c = NodeContact{};
}

void Rod::place_outside(std::size_t k) {
  x_[k] = entry_ + dir_ * (insertion_mm_ - from_tip_[k]);
  if (k + 1 < x_.size()) {
    t_[k] = dir_;
    d1_[k] = entry_d1_;
    theta_[k] = rotation_rad_;
  }
  node_contacts_[k] = NodeContact{};
}

void Rod::update_window() {
  // Last node not past the entry (depth <= 0; held within rounding while the insertion holds
  // still since the last step); max_insertion keeps it >= 1.
  const std::size_t kp = rod_detail::last_outside(from_tip_, insertion_mm_, stepped_insertion_mm_);
  first_ = kp - 1;
  first_free_ = kp + 1;
  for (std::size_t k = first_; k < first_free_; ++k) place_outside(k);
  // The clamp's hinge at the entry point (RodSettings::clamp_hinge_at_entry): the clamp edge
  // bends from as far ahead of the clamp node as that node is behind the entry, keeping at least
  // kClampEdgeFloor of the edge to the first free node. Not while an attached coil's clamp node
  // is its joint with the pusher or a pusher node: the pusher (500 times the coil's EI in the
  // bundled cases) is held straight in the lumen up to the joint, so the coil's end bends at the
  // clamp node, as without the hinge; hinged at the entry there, each coil's end jammed as it left
  // the catheter (convergence.md, "Coils hinged at the entry"). The switch is at the node crossing
  // that makes the joint the clamp node. A tool drawn back (hinge_while_drawn_back) is hinged too,
  // that word taken only when the clamp node changes, so a clamp node that holds still keeps its
  // clamp edge (and until that change its hinge walks to the entry point: below).
  clamp_shift_mm_ = 0.0;
  hinge_walking_ = false;
  if (kp != hinged_back_at_kp_) {
    hinged_back_ = drawn_back_;
    hinged_back_at_kp_ = kp;
    back_from_mm_ = -std::numeric_limits<double>::infinity();
  }
  const bool hinged = settings_.clamp_hinge_at_entry || hinged_back_;
  const bool pusher_at_clamp = spec_.detach_mm > 0.0 && from_tip_[kp] >= spec_.detach_mm - 1e-9;
  if (kp + 1 >= x_.size() || pusher_at_clamp) return;
  const double ceiling = (1.0 - kClampEdgeFloor) * rest_[kp];
  if (hinged) {
    clamp_shift_mm_ = std::clamp(from_tip_[kp] - insertion_mm_, 0.0, ceiling);
    return;
  }
  // Drawn back before the clamp node has changed: the hinge moves from the clamp node to the
  // entry point in proportion to the draw-back, reaching the entry as the next node crosses it,
  // so the switch to hinged at that crossing moves nothing (back_from_mm_: the insertion the
  // draw-back started from; pushed back past it, the clamp node bends again).
  if (drawn_back_ && stepped_insertion_mm_ > back_from_mm_) back_from_mm_ = stepped_insertion_mm_;
  const double to_crossing = back_from_mm_ - from_tip_[kp + 1];  // draw-back from there to the crossing
  const double drawn = back_from_mm_ - insertion_mm_;
  if (drawn > 0.0 && to_crossing > 0.0) clamp_shift_mm_ = std::min(ceiling, rest_[kp] * drawn / to_crossing);
  hinge_walking_ = clamp_shift_mm_ > 0.0;
}

glm::dvec3 Rod::point_at_from_tip(double from_tip_mm) const {
  const std::size_t n = x_.size();
  if (from_tip_mm >= std::min(insertion_mm_, from_tip_[first_])) return entry_ + dir_ * (insertion_mm_ - from_tip_mm);
  if (from_tip_mm <= 0.0) return x_[n - 1];
  // Between the entry and the first free node the tool runs from the entry point, not along the
  // chord from the clamp node behind the entry (which misses the entry by as much as the first
  // free node is off the entry line: a catheter following this wire had its tip put 0.15 mm
  // off its own tip, and its stiff last edge kinked).
  if (first_free_ < n && from_tip_mm > from_tip_[first_free_]) {
    const double span = insertion_mm_ - from_tip_[first_free_];
    const double u = span > 0.0 ? std::clamp((insertion_mm_ - from_tip_mm) / span, 0.0, 1.0) : 1.0;
    return entry_ + (x_[first_free_] - entry_) * u;
  }
  const std::size_t k = std::clamp(station_at(from_tip_, from_tip_mm), first_, n - 2);
  const double u = std::clamp((from_tip_[k] - from_tip_mm) / rest_[k], 0.0, 1.0);
  return x_[k] + (x_[k + 1] - x_[k]) * u;
}

glm::dvec3 Rod::point_at_depth(double depth_mm, glm::dvec3* tangent, std::size_t* node) const {
  const std::size_t n = x_.size();
  std::size_t k = station_at(from_tip_, insertion_mm_ - depth_mm);
  k = std::clamp(k, first_, n - 2);
  const double d0 = insertion_mm_ - from_tip_[k];
  const double u = std::clamp((depth_mm - d0) / rest_[k], 0.0, 1.0);
  if (tangent != nullptr) *tangent = t_[k];
  if (node != nullptr) *node = k;
  return x_[k] + (x_[k + 1] - x_[k]) * u;
}

TipPose Rod::tip() const {
  TipPose p;
  const std::size_t n = x_.size();
  p.position_mm = x_[n - 1];
  p.direction = t_[n - 2];
  p.normal = m1_[n - 2];
  return p;
}

glm::dvec3 Rod::clamp_force_mN() const { return clamp_force_; }

}  // namespace cathbox::tool

#include "tool/rod.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "base/portable_math.hpp"
#include "tool/banded_cholesky.hpp"
#include "tool/coil_shape.hpp"

namespace cathbox::tool {

namespace {

constexpr double kMilli = 1000.0;  // N -> mN
constexpr int kProjectionRounds = 6;  // wall / rod-rod projections alternated after a solve

// Rotates v by the rotation that takes unit vector `from` onto unit vector `to` (parallel transport).
// Rodrigues' formula with the unnormalised axis a = from x to (|a| = sin, 1 - cos = |a|^2 / (1 + cos)):
// no square root or division by the sine, which the frames call twice per edge and step.
glm::dvec3 transport(const glm::dvec3& v, const glm::dvec3& from, const glm::dvec3& to) {
  const glm::dvec3 a = glm::cross(from, to);
  const double s2 = glm::dot(a, a);
  const double c = glm::dot(from, to);
  if (s2 < 1e-28) return v;
  if (c < -0.5) {  // far from parallel: the normalised axis keeps 1 + cos away from a division
    const double s = std::sqrt(s2);
    const glm::dvec3 k = a / s;
    return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0 - c));
  }
  return v * c + glm::cross(a, v) + a * (glm::dot(a, v) / (1.0 + c));
}

glm::dvec3 perpendicular_unit(const glm::dvec3& t) {
  const glm::dvec3 a = std::abs(t.x) < 0.6 ? glm::dvec3(1, 0, 0)
                       : std::abs(t.y) < 0.6 ? glm::dvec3(0, 1, 0)
                                              : glm::dvec3(0, 0, 1);
  return glm::normalize(a - t * glm::dot(a, t));
}

struct BlockAdder {
  BandedCholesky& m;
  std::size_t first;
  bool enabled;
  void operator()(std::size_t a, std::size_t b, const glm::dmat3& block) const {
    if (!enabled) return;
    if (a < b) {
      m.add_block(b - first, a - first, glm::transpose(block));
      return;
    }
    m.add_block(a - first, b - first, block);
  }
};

double finite_or(double v, double fallback) { return std::isfinite(v) ? v : fallback; }

// A point on the chord from b to c (inside the circle through a, b and c; a on either side of
// b) moved out along the circle's radius onto it; false when the three are (nearly) in line.
// The chord's point a fraction u along turns to the circle's point about a fraction u of the
// arc along (the difference is of the order of the arc angle cubed): moving every node of a
// circular polygon this way turns it rigidly, its edge lengths and turning angles kept.
bool onto_arc(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& chord, glm::dvec3& out) {
  const glm::dvec3 p = a - b;
  const glm::dvec3 q = c - b;
  const glm::dvec3 w = glm::cross(p, q);
  const double w2 = glm::dot(w, w);
  if (!(w2 > 1e-12 * glm::dot(p, p) * glm::dot(q, q))) return false;
  const glm::dvec3 centre = b + glm::cross(glm::dot(p, p) * q - glm::dot(q, q) * p, w) / (2.0 * w2);
  const glm::dvec3 r = chord - centre;
  const double len = glm::length(r);
  if (!(len > 0.0)) return false;
  out = centre + r * (glm::length(b - centre) / len);
  return true;
}

}  // namespace

struct Rod::NodeContact {
  bool has_plane = false;
  bool active = false;  // held on its plane in this step's solve (active set)
  bool has_second = false;  // a second plane (crease of a meshed wall): normal force only
  bool active2 = false;
  glm::dvec3 point2{0.0};
  glm::dvec3 normal2{0.0};
  double normal_force2 = 0.0;
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0};
  std::int32_t segment = -1;
  WallHint hint;
  glm::dvec3 query_pos{0.0};
  double clearance = -1.0;  // node surface clearance when last probed; < 0: probe again
  bool anchored = false;
  glm::dvec3 anchor{0.0};
  double twist_anchor = 0.0;
  double normal_force = 0.0;
  glm::dvec3 friction{0.0};
};

Rod::Rod(const ToolSpec& spec, const RodSettings& settings) : spec_(spec), settings_(settings) {
  if (spec_.sections.empty()) spec_.sections.push_back(ToolSection{100.0});
  length_mm_ = spec_.length_mm();
  const double h_tip = std::max(0.05, spec_.tip_spacing_mm);
  const double h_max = std::max(h_tip, spec_.max_spacing_mm);
  // A detachable coil ends at a node (its detachment zone).
  const double must = spec_.detach_mm > 0.0 && spec_.detach_mm < length_mm_ ? spec_.detach_mm : -1.0;
  // Material stations from the tip: fine over the tip zone, then growing to h_max.
  std::vector<double> s{0.0};
  for (;;) {
    const double u = s.back();
    const double ramp = std::clamp((u - spec_.tip_zone_mm) / std::max(1e-9, 2.0 * spec_.tip_zone_mm), 0.0, 1.0);
    const double h = h_tip + (h_max - h_tip) * ramp;
    if (must > u && must <= u + h) {
      if (must - u < 0.3 * h && u > 0.0) s.back() = must; else s.push_back(must);
      continue;
    }
    if (u + h >= length_mm_ - 0.3 * h) break;
    s.push_back(u + h);
  }
  s.push_back(length_mm_);
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
  for (std::size_t k = 0; k < n; ++k) {
    const double left = k > 0 ? rest_[k - 1] : 0.0;
    const double right = k + 1 < n ? rest_[k] : 0.0;
    voronoi_[k] = 0.5 * (left + right);
    // Section holding this station.
    double from_proximal = length_mm_ - from_tip_[k];
    const ToolSection* sec = &spec_.sections.back();
    for (const ToolSection& candidate : spec_.sections) {
      if (from_proximal <= candidate.length_mm) {
        sec = &candidate;
        break;
      }
      from_proximal -= candidate.length_mm;
    }
    radius_[k] = 0.5 * sec->outer_diameter_mm;
    inner_radius_[k] = 0.5 * spec_.inner_diameter_mm;
    ei_[k] = sec->bending_stiffness_Nmm2 * kMilli;
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
  size_scratch();
  set_entry(glm::dvec3(0.0), glm::dvec3(0, 0, 1));
}

Rod::Rod() = default;

void Rod::size_scratch() {
  const std::size_t n = x_.size();
  grad_.assign(3 * n, 0.0);
  delta_.assign(3 * n, 0.0);
  work_.assign(3 * n, 0.0);
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
  matrix_ = std::make_unique<BandedCholesky>(n);
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
  for (std::size_t k = 0; k < x_.size(); ++k) place_outside(k);
  for (NodeContact& c : node_contacts_) c = NodeContact{};
  contacts_.clear();
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

namespace {
// Index of the station holding a distance from the tip (stations descend with k).
std::size_t station_at(const std::vector<double>& from_tip, double d) {
  std::size_t lo = 0;
  std::size_t hi = from_tip.size() - 1;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (from_tip[mid] >= d) lo = mid; else hi = mid;
  }
  return lo;
}

// station_at by a walk from `hint` (updated; kNoStation: search): the last index <= size - 2
// whose distance is >= d, or 0 (stations descend strictly).
std::size_t station_near(const std::vector<double>& from_tip, double d, std::size_t& hint) {
  if (hint == Rod::kNoStation) {
    hint = station_at(from_tip, d);
    return hint;
  }
  std::size_t k = std::min(hint, from_tip.size() - 2);
  while (k > 0 && from_tip[k] < d) --k;
  while (k + 2 < from_tip.size() && from_tip[k + 1] >= d) ++k;
  hint = k;
  return k;
}
}  // namespace

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
  const std::size_t n = x_.size();
  // Last node not past the entry (depth <= 0); max_insertion keeps it >= 1.
  std::size_t kp = station_at(from_tip_, insertion_mm_);
  if (from_tip_[kp + 1 < n ? kp + 1 : kp] >= insertion_mm_) kp = kp + 1 < n ? kp + 1 : kp;
  if (kp < 1) kp = 1;
  first_ = kp - 1;
  first_free_ = kp + 1;
  for (std::size_t k = first_; k < first_free_; ++k) place_outside(k);
}

void Rod::advect(double delta_mm) {
  // Predictor: every free node slides along the present centreline by the insertion change
  // (follow the leader); the elastic solve then corrects the shape. Beyond the tip the path
  // continues straight; proximal of the window it is the entry line.
  const std::size_t n = x_.size();
  if (delta_mm == 0.0) return;
  const double old_insertion = insertion_mm_ - delta_mm;
  const std::size_t new_kp = [&] {
    std::size_t kp = station_at(from_tip_, insertion_mm_);
    if (kp + 1 < n && from_tip_[kp + 1] >= insertion_mm_) ++kp;
    return std::max<std::size_t>(kp, 1);
  }();
  std::size_t j = first_;  // segment [j, j+1] of the old curve holding the target station
  for (std::size_t k = new_kp + 1; k < n; ++k) {
    const double s = from_tip_[k] - delta_mm;  // station (old curve) the node moves to
    if (s >= from_tip_[first_]) {
      x_pred_[k] = entry_ + dir_ * (old_insertion - s);
    } else if (s <= 0.0) {
      // Ahead of the tip: along the leader (a wire beyond this catheter) or straight on.
      const double leader_station = leader_ != nullptr ? leader_insertion_mm_ - (old_insertion - s) : -1.0;
      if (leader_ != nullptr && leader_station >= 0.0) {
        x_pred_[k] = leader_->point_at_from_tip(leader_station);
      } else {
        x_pred_[k] = x_[n - 1] + t_[n - 2] * (-s);
      }
    } else {
      while (j + 2 < n && from_tip_[j + 1] > s) ++j;
      while (j > first_ && from_tip_[j] < s) --j;
      const double u = std::clamp((from_tip_[j] - s) / rest_[j], 0.0, 1.0);
      x_pred_[k] = x_[j] + (x_[j + 1] - x_[j]) * u;
      // A coil's loops: along the circles through the neighbours instead of the chord (the
      // mean of the circles before and after the edge), so the slide keeps edge lengths.
      glm::dvec3 before, after;
      const glm::dvec3 chord = x_pred_[k];
      const bool has_before = settings_.arc_predictor && j > first_ && onto_arc(x_[j - 1], x_[j], x_[j + 1], chord, before);
      const bool has_after = settings_.arc_predictor && j + 2 < n && onto_arc(x_[j + 2], x_[j + 1], x_[j], chord, after);
      if (has_before && has_after) x_pred_[k] = 0.5 * (before + after);
      else if (has_before) x_pred_[k] = before;
      else if (has_after) x_pred_[k] = after;
    }
  }
  for (std::size_t k = new_kp + 1; k < n; ++k) x_[k] = x_pred_[k];
}

void Rod::move_entry(const glm::dvec3& point_mm, const glm::dvec3& direction, const glm::dvec3& reference) {
  const double len = glm::length(direction);
  if (!(len > 1e-12) || !std::isfinite(len) || !std::isfinite(point_mm.x + point_mm.y + point_mm.z)) return;
  // Predictor: the free part near the entry follows the entry's move (the carrier's tip), fading
  // out over kFollowEntry_mm along the tool, so the clamp does not tear at the first nodes.
  const glm::dvec3 moved = point_mm - entry_;
  if (glm::dot(moved, moved) > 0.0 && first_free_ < x_.size()) {
    constexpr double kFollowEntry_mm = 10.0;
    const double s0 = from_tip_[first_free_ - 1];
    for (std::size_t k = first_free_; k < x_.size(); ++k) {
      const double w = 1.0 - (s0 - from_tip_[k]) / kFollowEntry_mm;
      if (w <= 0.0) break;
      x_[k] += moved * w;
    }
  }
  entry_ = point_mm;
  dir_ = direction / len;
  const glm::dvec3 r = reference - dir_ * glm::dot(reference, dir_);
  const double rl = glm::length(r);
  entry_d1_ = rl > 1e-9 ? r / rl : perpendicular_unit(dir_);
}

glm::dvec3 Rod::point_at_from_tip(double from_tip_mm) const {
  const std::size_t n = x_.size();
  if (from_tip_mm >= from_tip_[first_]) return entry_ + dir_ * (insertion_mm_ - from_tip_mm);
  if (from_tip_mm <= 0.0) return x_[n - 1];
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

bool Rod::refresh_contacts(const WallModel& wall, bool only_moved) {
  const std::size_t n = x_.size();
  bool active_changed = false;
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& c = node_contacts_[k];
    const double moved = glm::length(x_[k] - c.query_pos);
    if (c.clearance >= 0.0) {
      if (only_moved && moved < settings_.requery_move_mm) continue;
      if (!c.has_plane && moved < c.clearance - settings_.contact_margin_mm) continue;
    }
    WallProbe probe;
    probe.center_mm = x_[k];
    probe.radius_mm = radius_[k];
    probe.range_mm = settings_.query_range_mm;
    probe.margin_mm = settings_.contact_margin_mm;
    probe.depth_mm = insertion_mm_ - from_tip_[k];
    WallContact wc;
    c.query_pos = x_[k];
    active_changed = active_changed || c.active;
    if (wall.probe(probe, c.hint, wc) && std::isfinite(wc.distance_mm)) {
      c.clearance = std::max(0.0, wc.distance_mm - radius_[k]);
      c.has_plane = wc.distance_mm - radius_[k] < settings_.contact_margin_mm;
      c.point = wc.point_mm;
      c.normal = wc.normal;
      c.has_second = c.has_plane && wc.has_second;
      c.point2 = wc.second_point_mm;
      c.normal2 = wc.second_normal;
      if (!c.has_second) c.active2 = false;
      c.segment = wc.segment;
    } else {
      c.clearance = settings_.query_range_mm;
      c.has_plane = false;
    }
    if (c.has_plane && !c.anchored) {
      c.anchored = true;
      c.anchor = x_[k];
      c.twist_anchor = theta_[std::min(k, n - 2)];
    } else if (!c.has_plane) {
      c.anchored = false;
      c.active = false;
      c.has_second = false;
      c.active2 = false;
    }
  }
  return active_changed;
}

void Rod::step(double dt_s, const WallModel& wall, const RodObstacles* obstacles) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) dt_s = 1e-3;
  const std::size_t n = x_.size();
  const std::size_t old_first = first_;
  for (std::size_t k = std::min(old_first, first_); k < n; ++k) x_start_[k] = x_[k];
  if (!free_) {
    const double advance =
        std::isfinite(material_advance_mm_) ? material_advance_mm_ : insertion_mm_ - stepped_insertion_mm_;
    material_advance_mm_ = std::numeric_limits<double>::quiet_NaN();
    advect(advance);
    stepped_insertion_mm_ = insertion_mm_;
    update_window();
  }
  for (std::size_t k = first_; k < old_first; ++k) x_start_[k] = x_[k];
  for (std::size_t k = first_; k + 1 < n; ++k) theta_start_[k] = theta_[k];

  edge_contacts_.clear();
  if (first_free_ < n) {
    if (compressed_) seed_buckling();
    // Warm start from the last converged step's motion (never after a compressed one: a
    // jammed, buckled tool extrapolated keeps shaking). solved_move_ then keeps where this
    // step's solve starts from (the advected position), until the step's own motion is known.
    const bool warm = warm_ok_ && !compressed_ && settings_.warm_start != 0.0;
    for (std::size_t k = first_free_; k < n; ++k) {
      const glm::dvec3 from = x_[k];
      if (warm && k >= warm_first_) x_[k] += solved_move_[k] * settings_.warm_start;
      solved_move_[k] = from;
    }
    warm_ok_ = false;
    update_weights(dt_s);
    refresh_contacts(wall, false);
    if (obstacles != nullptr) gather_obstacles(*obstacles);
    const std::size_t dofs = 3 * (n - first_);
    const std::size_t free0 = 3 * (first_free_ - first_);
    const int iterations = std::max(1, settings_.newton_iterations);
    // Active set: nodes touching now or at the end of the last step are held on their plane.
    for (std::size_t k = first_free_; k < n; ++k) {
      NodeContact& nc = node_contacts_[k];
      nc.active = nc.has_plane && (nc.normal_force > 0.0 || plane_gap(k) > 0.0);
      nc.active2 = nc.has_second && (nc.normal_force2 > 0.0 || second_gap(k) > 0.0);
    }
    int activations = 0;
    // Newton with a lazily refreshed Hessian: it is assembled and factored again only when the
    // active set or an active contact plane changed, or a step failed to lower the energy;
    // otherwise only the gradient is rebuilt (chord iterations).
    bool refactor = true;
    bool rejoin = false;
    std::size_t rejoin_from = n;  // first node whose wall terms the rejoin amended
    int rounds = iterations;
    std::fill(held_gap_.begin(), held_gap_.end(), std::numeric_limits<double>::quiet_NaN());
    bool stepped = false;  // last_step_ holds an update of this step
    for (int it = 0; it < rounds; ++it) {
      if (rejoin) {
        // Amend the assembly (the factorisation leaves it intact) with the wall terms of the
        // nodes that joined.
        const BlockAdder add{*matrix_, first_, true};
        const double kc = settings_.contact_stiffness_mN_per_mm;
        rejoin_from = n;
        for (std::size_t k = first_free_; k < n; ++k) {
          if (!joined_[k]) continue;
          rejoin_from = std::min(rejoin_from, k);
          const NodeContact& nc = node_contacts_[k];
          const std::size_t d = 3 * (k - first_);
          for (int j = 0; j < 2; ++j) {
            if (!(joined_[k] & (1 << j))) continue;
            const glm::dvec3& normal = j == 0 ? nc.normal : nc.normal2;
            const double phi = j == 0 ? plane_gap(k) : second_gap(k);
            add(k, k, kc * glm::outerProduct(normal, normal));
            grad_[d] += normal.x * kc * phi;
            grad_[d + 1] += normal.y * kc * phi;
            grad_[d + 2] += normal.z * kc * phi;
            energy_ += 0.5 * kc * phi * phi;
          }
          joined_[k] = 0;
        }
        rejoin = false;
      } else {
        assemble(refactor);
        for (std::size_t k = first_free_; k < n; ++k) x_pred_[k] = x_[k];  // where grad_ holds
      }
      // After a join only the joined nodes' diagonal blocks changed: factor again from the
      // first of them (the rows before it are the last factorisation's, bit for bit).
      if (refactor && rejoin_from < n) {
        matrix_->refactor_from(rejoin_from - first_);
      } else if (refactor) {
        matrix_->factor(first_free_ - first_);
      }
      rejoin_from = n;
      const bool fresh = refactor;
      refactor = !settings_.reuse_hessian;
      for (std::size_t i = 0; i < dofs; ++i) delta_[i] = i >= free0 ? -grad_[i] : 0.0;
      matrix_->solve(delta_.data());
      double largest = 0.0;
      for (std::size_t k = first_free_; k < n; ++k) {
        const std::size_t d = 3 * (k - first_);
        const double m = std::sqrt(delta_[d] * delta_[d] + delta_[d + 1] * delta_[d + 1] + delta_[d + 2] * delta_[d + 2]);
        largest = std::max(largest, m);
      }
      if (!std::isfinite(largest)) break;  // keep the previous positions; never propagate NaN
      // Nodes off the wall that the step would carry into it join the active set; solve again.
      bool joined = false;
      for (std::size_t k = first_free_; k < n && activations < 3; ++k) {
        NodeContact& nc = node_contacts_[k];
        if (!nc.has_plane) continue;
        const std::size_t d = 3 * (k - first_);
        const glm::dvec3 step(delta_[d], delta_[d + 1], delta_[d + 2]);
        if (!nc.active && plane_gap(k) + glm::dot(nc.normal, step) > 0.0) {
          nc.active = true;
          joined = true;
          joined_[k] |= 1;
        }
        if (nc.has_second && !nc.active2 && second_gap(k) + glm::dot(nc.normal2, step) > 0.0) {
          nc.active2 = true;
          joined = true;
          joined_[k] |= 2;
        }
      }
      if (joined) {
        ++activations;
        if (it + 1 == rounds && rounds < iterations + 2) ++rounds;  // solve with them held
        refactor = true;
        rejoin = true;
        continue;
      }
      double scale = largest > settings_.max_node_step_mm ? settings_.max_node_step_mm / largest : 1.0;
      double aim = 1.0;  // the fraction of the Newton update the step means to take
      if (stepped && settings_.damp_reversals && largest * scale < settings_.trust_step_mm) {
        // An update too small for the line search that nearly undoes the last one is a
        // two-cycle (friction at its stick-slip edge, a crease plane let go and taken back):
        // half of it lands between the two states, where the solution is.
        double dot = 0.0, now = 0.0, before = 0.0;
        for (std::size_t i = free0; i < dofs; ++i) {
          dot += delta_[i] * last_step_[i];
          now += delta_[i] * delta_[i];
          before += last_step_[i] * last_step_[i];
        }
        if (dot < -0.9 * std::sqrt(now * before)) scale *= 0.5, aim = 0.5;
      }
      // Backtracking line search on the step energy (contacts and friction are non-smooth).
      const double e0 = energy_;
      double slope = 0.0;
      for (std::size_t i = free0; i < dofs; ++i) slope += grad_[i] * delta_[i];
      for (int tries = 0;; ++tries) {
        for (std::size_t k = first_free_; k < n; ++k) {
          const std::size_t d = 3 * (k - first_);
          x_[k] = x_pred_[k] + glm::dvec3(delta_[d], delta_[d + 1], delta_[d + 2]) * scale;
        }
        // Small steps near convergence are taken as they are.
        if (tries >= 6 || slope >= 0.0 || largest * scale < settings_.trust_step_mm ||
            energy() <= e0 + 1e-4 * scale * slope) {
          break;
        }
        scale *= 0.5;
        if (!fresh) refactor = true;  // a stale Hessian gave a poor step
      }
      for (std::size_t i = free0; i < dofs; ++i) last_step_[i] = delta_[i] * scale;
      stepped = true;
      // Nodes the wall would have to pull leave the active set; nodes the step carried into
      // the wall (after the activation rounds ran out) join it for the next iteration.
      // `entered`: one of them is deeper than a hundredth of the penetration limit (the
      // convergence test does not stop on it: the end of the step might clamp it); `deep`: a
      // held node is past the limit.
      bool entered = false;
      bool deep = false;
      for (std::size_t k = first_free_; k < n; ++k) {
        const NodeContact& nc = node_contacts_[k];
        const std::size_t d = 3 * (k - first_);
        const glm::dvec3 rest(delta_[d], delta_[d + 1], delta_[d + 2]);
        held_gap_[k] = nc.active ? plane_gap(k) + (aim - scale) * glm::dot(nc.normal, rest)
                                 : std::numeric_limits<double>::quiet_NaN();
      }
      const auto update = [&](bool& active, double phi, double allowed) {
        if (active && phi < -1e-9) {
          active = false;
          refactor = true;
        } else if (!active && phi > 0.0) {
          active = true;
          refactor = true;
          entered = entered || phi > 0.01 * allowed;
        } else {
          deep = deep || (active && phi > allowed);
        }
      };
      for (std::size_t k = first_free_; k < n; ++k) {
        NodeContact& nc = node_contacts_[k];
        if (!nc.has_plane) continue;
        const double allowed = settings_.max_penetration_ratio * radius_[k];
        update(nc.active, plane_gap(k), allowed);
        if (nc.has_second) update(nc.active2, second_gap(k), allowed);
      }
      if (refresh_contacts(wall, true)) refactor = true;
      if (obstacles != nullptr) {
        // A node the re-probe finds in the wall joins the active set now: among other rods
        // (a coil in its sac) the joins of the iterations above are soon spent, and a node left
        // out was carried deep into the wall and thrown back by the projection below.
        for (std::size_t k = first_free_; k < n; ++k) {
          NodeContact& nc = node_contacts_[k];
          if (!nc.has_plane) continue;
          if (!nc.active && plane_gap(k) > 0.0) nc.active = true, refactor = true;
          if (nc.has_second && !nc.active2 && second_gap(k) > 0.0) nc.active2 = true, refactor = true;
        }
      }
      if (obstacles != nullptr) {
        // Planes of other rods are taken again once a node has moved half the margin.
        const double limit = 0.5 * obstacles->margin_mm();
        for (std::size_t k = first_free_; k < n; ++k) {
          if (glm::length(x_[k] - gathered_at_[k]) > limit) {
            gather_obstacles(*obstacles);
            refactor = true;
            break;
          }
        }
      }
      last_iterations_ = it + 1;
      if (largest * scale < settings_.convergence_mm && !entered) {
        warm_ok_ = true;
        break;
      }
      // A node left in the wall at the end would be clamped at the penetration limit, which
      // reads as the contact cap: up to two more iterations hold it.
      if ((entered || deep) && it + 1 == rounds && rounds < iterations + 2) ++rounds;
    }
    // A node held in the last iteration but past the limit (the step was cut to
    // max_node_step_mm) goes where the Newton step it aimed at (the full one, half of a damped
    // reversal) puts it along the wall normal: its
    // force is the penalty's at the linearised equilibrium, not the clamp's cap.
    for (std::size_t k = first_free_; k < n; ++k) {
      const NodeContact& nc = node_contacts_[k];
      const double phi = nc.has_plane ? plane_gap(k) : 0.0;
      const double allowed = settings_.max_penetration_ratio * radius_[k];
      if (nc.active && phi > allowed && held_gap_[k] < allowed) x_[k] -= nc.normal * (phi - std::max(0.0, held_gap_[k]));
    }
    refresh_contacts(wall, true);
    limit_penetration();
    for (std::size_t k = first_free_; k < n; ++k) solved_move_[k] = x_[k] - solved_move_[k];
    warm_first_ = first_free_;
    // Among other rods the wall and rod-rod projections alternate (a loop pressed on the sac by
    // the next), each rod-rod round on planes gathered afresh: planes held from the iterations
    // split a gap both sides have since moved across, and projecting on them pushed loops into
    // the wall and into each other.
    for (int round = 0; round < (obstacles != nullptr ? kProjectionRounds : 1); ++round) {
      if (round > 0) limit_penetration();
      if (obstacles != nullptr) gather_obstacles(*obstacles);
      if (!finish_edge_contacts()) break;
    }
    // The force on the clamp at the final state, to first order from the last assembly:
    // g_p += K_pf (x - x_assembled). A rod among other rods (a coil, the catheter it leaves)
    // often ends its step before its contacts settle; its clamp takes the last Newton step
    // whole instead (the free part at the linearised equilibrium: g_p - K_pf K_ff^-1 g_f), so
    // the residual of its stiff axial springs and of the final projections stays out of the hand.
    bool whole = obstacles != nullptr || settings_.linearised_clamp;
    for (std::size_t i = free0; whole && i < dofs; ++i) whole = std::isfinite(delta_[i]);
    for (std::size_t k = first_free_; k < n; ++k) {
      const std::size_t d = 3 * (k - first_);
      const glm::dvec3 moved = whole ? glm::dvec3(delta_[d], delta_[d + 1], delta_[d + 2]) : x_[k] - x_pred_[k];
      work_[d] = moved.x;
      work_[d + 1] = moved.y;
      work_[d + 2] = moved.z;
    }
    matrix_->multiply_add(work_.data(), grad_.data(), 0, free0, free0, dofs);
  } else {
    hand_force_mN_ = 0.0;
    warm_ok_ = false;  // all in the catheter: its last solved motion is no guide when it comes out
  }
  update_frames();
  solve_twist(dt_s);
  finish_contacts();
  compute_force_law(dt_s);
}


double Rod::plane_gap(std::size_t k) const {
  const NodeContact& nc = node_contacts_[k];
  return glm::dot(nc.normal, x_[k] - nc.point) + radius_[k];
}

double Rod::second_gap(std::size_t k) const {
  const NodeContact& nc = node_contacts_[k];
  return glm::dot(nc.normal2, x_[k] - nc.point2) + radius_[k];
}

void Rod::update_weights(double dt_s) {
  // What the assembly and the line search would otherwise divide for at every call.
  const std::size_t n = x_.size();
  const double ea = spec_.axial_stiffness_N * kMilli;
  for (std::size_t k = first_; k + 1 < n; ++k) axial_k_[k] = ea / rest_[k];
  // At the clamp vertex only the half edge past it bends (the clamp sits at the vertex).
  for (std::size_t i = first_ + 1; i + 1 < n; ++i) {
    bend_w_[i] = (ei_[i] + ei_extra_[i]) / (i == first_ + 1 && !free_ ? 0.5 * rest_[i] : voronoi_[i]);
  }
  for (std::size_t k = first_free_; k < n; ++k) drag_k_[k] = solver_drag(k) / dt_s;
}

glm::dvec3 Rod::bend_residual(std::size_t i, const glm::dvec3& ta, const glm::dvec3& tb) const {
  // Bending residual on the unit tangents around vertex i: r = t_b - t_a - (rest turn towards
  // m1). |t_b - t_a| is 2 sin(phi/2) of the turning angle phi: the discrete curvature for small
  // angles, and bounded for kinks, which keeps the Gauss-Newton steps good.
  glm::dvec3 r = tb - ta;
  if (kturn1_[i] != 0.0) r -= (m1_[i - 1] + m1_[i]) * (0.5 * kturn1_[i]);
  if (kturn2_[i] != 0.0) r -= (m2_[i - 1] + m2_[i]) * (0.5 * kturn2_[i]);
  return r;
}

void Rod::assemble(bool hessian) {
  // Gradient, energy and Hessian in one pass along the rod: each edge's length and tangent
  // once (its stretching and the bending at the vertices either side share them), and each
  // block row written as soon as its last term is known. The Gauss-Newton Hessian in terms of
  // the edge projectors P_e = I - t_e t_e^T:
  //   stretching of edge e: ks_e I + (ks'_e - ks_e) P_e, ks = EA / rest, ks' = ks max(0, 1 - rest / len);
  //   bending at vertex i (edges a = i - 1, b = i): w J^T J with J = [P_a / l_a, -(P_a / l_a + P_b / l_b),
  //   P_b / l_b] on nodes i - 1, i, i + 1, whose blocks are w P_a / l_a^2, w P_b / l_b^2 and
  //   multiples of M_i = P_b P_a = I - t_a t_a^T - t_b t_b^T + (t_a . t_b) t_b t_a^T.
  // Block row k is then
  //   A(k, k)     = nodal_k + (ks_k + ks_{k-1}) I + c_k P_k + c_{k-1} P_{k-1} + g_k (M_k + M_k^T),
  //   A(k, k - 1) = -ks_{k-1} I - c_{k-1} P_{k-1} - g_k M_k - g_{k-1} M_{k-1},
  //   A(k, k - 2) = g_{k-1} M_{k-1},
  // with c_e = ks'_e - ks_e + (w_e + w_{e+1}) / l_e^2 and g_i = w_i / (l_{i-1} l_i) (w = 0 off the
  // bending vertices first_ + 1 .. n - 2).
  const std::size_t n = x_.size();
  const std::size_t dofs = 3 * (n - first_);
  std::fill(grad_.begin(), grad_.begin() + static_cast<std::ptrdiff_t>(dofs), 0.0);
  energy_ = 0.0;
  auto add_grad = [&](std::size_t k, const glm::dvec3& g) {
    const std::size_t d = 3 * (k - first_);
    grad_[d] += g.x;
    grad_[d + 1] += g.y;
    grad_[d + 2] += g.z;
  };
  const glm::dmat3 identity(1.0);
  const glm::dmat3 zero(0.0);
  const double kc = settings_.contact_stiffness_mN_per_mm;
  const double kt = kc * settings_.stick_stiffness_ratio;
  const auto vertex = [&](std::size_t i) { return i >= first_ + 1 && i + 1 < n; };
  if (hessian) matrix_->resize(n - first_);

  // Edge k - 1 and vertex k - 1, carried from the last node.
  glm::dvec3 u_prev(0.0);
  double inv_prev = 1.0;  // 1 / l_{k-1}
  glm::dmat3 p_prev(0.0), m_prev(0.0);
  double ks_prev = 0.0, c_prev = 0.0, g_prev = 0.0;
  double w = 0.0;  // vertex k's bending weight (first_ is no vertex)
  for (std::size_t k = first_; k < n; ++k) {
    // Edge k: node k -> k + 1.
    glm::dvec3 u(0.0);
    double inv = 1.0, ks = 0.0, c = 0.0;
    glm::dmat3 p(0.0);
    const double w_next = vertex(k + 1) ? bend_w_[k + 1] : 0.0;
    if (k + 1 < n) {
      const glm::dvec3 e = x_[k + 1] - x_[k];
      const double len = std::max(glm::length(e), 1e-12);
      inv = 1.0 / len;
      u = e * inv;
      ks = axial_k_[k];
      const glm::dvec3 f = u * (ks * (len - rest_[k]));
      energy_ += 0.5 * ks * (len - rest_[k]) * (len - rest_[k]);
      add_grad(k + 1, f);
      add_grad(k, -f);
      if (hessian) {
        p = identity - glm::outerProduct(u, u);
        c = ks * std::max(0.0, 1.0 - rest_[k] * inv) - ks + (w + w_next) * (inv * inv);
      }
    }
    // Vertex k, between edges k - 1 and k.
    double g = 0.0;
    glm::dmat3 m(0.0);
    if (vertex(k)) {
      const glm::dvec3 r = bend_residual(k, u_prev, u);
      const double ca = w * inv_prev;
      const double cb = w * inv;
      const glm::dvec3 ga = (u_prev * glm::dot(u_prev, r) - r) * ca;  // w ja^T r, ja = -P_a / l_a
      const glm::dvec3 gb = (r - u * glm::dot(u, r)) * cb;            // w jb^T r, jb = P_b / l_b
      add_grad(k - 1, -ga);
      add_grad(k, ga - gb);
      add_grad(k + 1, gb);
      energy_ += 0.5 * w * glm::dot(r, r);
      if (hessian) {
        g = ca * inv;
        m = identity - glm::outerProduct(u_prev, u_prev) - glm::outerProduct(u, u) +
            glm::outerProduct(u, u_prev) * glm::dot(u_prev, u);
      }
    }
    // Wall contacts, friction, drag and loads on the free nodes: one block on the diagonal.
    glm::dmat3 h = zero;
    if (k >= first_free_) {
      const double cd = drag_k_[k];
      const glm::dvec3 moved = x_[k] - x_start_[k];
      const glm::dvec3 load = load_[k] + coupling_[k];
      add_grad(k, moved * cd - load);
      h = identity * cd;
      energy_ += 0.5 * cd * glm::dot(moved, moved) - glm::dot(load, x_[k]);
      if (grip_limit_[k] > 0.0) {
        const double kg = kc * settings_.stick_stiffness_ratio;
        const glm::dvec3 rel = x_[k] - grip_anchor_[k];
        const double rel_len = glm::length(rel);
        const double limit = grip_limit_[k];
        if (kg * rel_len <= limit) {
          add_grad(k, rel * kg);
          h += identity * kg;
          energy_ += 0.5 * kg * rel_len * rel_len;
        } else {
          const glm::dvec3 ru = rel / rel_len;
          add_grad(k, ru * limit);
          h += (limit / rel_len) * (identity - glm::outerProduct(ru, ru));
          energy_ += limit * rel_len - 0.5 * limit * limit / kg;
        }
      }
      friction_limit_[k] = 0.0;
      NodeContact& nc = node_contacts_[k];
      if (nc.has_plane && nc.active2) {
        const double phi2 = second_gap(k);
        add_grad(k, nc.normal2 * (kc * phi2));
        h += kc * glm::outerProduct(nc.normal2, nc.normal2);
        energy_ += 0.5 * kc * phi2 * phi2;
      }
      if (nc.has_plane && nc.active) {
        const double phi = plane_gap(k);
        const glm::dmat3 nn = glm::outerProduct(nc.normal, nc.normal);
        add_grad(k, nc.normal * (kc * phi));
        h += kc * nn;
        energy_ += 0.5 * kc * phi * phi;
        if (spec_.friction > 0.0) {
          const glm::dmat3 pt = identity - nn;
          const glm::dvec3 slip = pt * (x_[k] - nc.anchor);
          const double slip_len = glm::length(slip);
          // The slip limit uses the normal force of the previous step, so within a step friction
          // is a fixed convex potential and the iterations converge.
          const double limit = spec_.friction * nc.normal_force;
          friction_limit_[k] = limit;
          if (kt * slip_len <= limit) {
            add_grad(k, slip * kt);
            h += kt * pt;
            energy_ += 0.5 * kt * slip_len * slip_len;
          } else {
            energy_ += limit * slip_len - 0.5 * limit * limit / kt;
            const glm::dvec3 sd = slip / slip_len;
            add_grad(k, sd * limit);
            h += (limit / slip_len) * (pt - glm::outerProduct(sd, sd));
          }
        }
      }
    }
    if (hessian) {
      const glm::dmat3 diag = h + identity * (ks + ks_prev) + p * c + p_prev * c_prev + (m + glm::transpose(m)) * g;
      const glm::dmat3 sub1 = -(identity * ks_prev + p_prev * c_prev + m * g + m_prev * g_prev);
      matrix_->set_row(k - first_, diag, sub1, m_prev * g_prev);
    }
    u_prev = u;
    inv_prev = inv;
    p_prev = p;
    m_prev = m;
    ks_prev = ks;
    c_prev = c;
    g_prev = g;
    w = w_next;
  }

  // Other rods (and the rod's own far parts): one-sided penalty on the gathered planes.
  const BlockAdder add{*matrix_, first_, hessian};
  for (const EdgeContact& ec : edge_contacts_) {
    const double phi = edge_gap(ec);
    if (phi <= 0.0) continue;
    const std::size_t a = ec.edge;
    const double wa = 1.0 - ec.s;
    const double wb = ec.s;
    energy_ += 0.5 * kc * phi * phi;
    if (a >= first_free_) add_grad(a, -ec.normal * (kc * phi * wa));
    if (a + 1 >= first_free_) add_grad(a + 1, -ec.normal * (kc * phi * wb));
    if (!hessian) continue;
    const glm::dmat3 nn = kc * glm::outerProduct(ec.normal, ec.normal);
    if (a >= first_free_) add(a, a, nn * (wa * wa));
    if (a + 1 >= first_free_) add(a + 1, a + 1, nn * (wb * wb));
    if (a >= first_free_) add(a + 1, a, nn * (wa * wb));
  }
}

double Rod::energy() const {
  // The energy whose gradient assemble() builds, with the friction limits of the last assembly.
  const std::size_t n = x_.size();
  double e = 0.0;
  glm::dvec3 u_prev(0.0);  // edge k - 1's tangent
  for (std::size_t k = first_; k + 1 < n; ++k) {
    const glm::dvec3 edge = x_[k + 1] - x_[k];
    const double len = std::max(glm::length(edge), 1e-12);
    const double stretch = len - rest_[k];
    e += 0.5 * axial_k_[k] * stretch * stretch;
    const glm::dvec3 u = edge * (1.0 / len);
    if (k >= first_ + 1) {
      const glm::dvec3 r = bend_residual(k, u_prev, u);
      e += 0.5 * bend_w_[k] * glm::dot(r, r);
    }
    u_prev = u;
  }
  const double kc = settings_.contact_stiffness_mN_per_mm;
  const double kt = kc * settings_.stick_stiffness_ratio;
  for (const EdgeContact& ec : edge_contacts_) {
    const double phi = edge_gap(ec);
    if (phi > 0.0) e += 0.5 * kc * phi * phi;
  }
  for (std::size_t k = first_free_; k < n; ++k) {
    const glm::dvec3 moved = x_[k] - x_start_[k];
    e += 0.5 * drag_k_[k] * glm::dot(moved, moved) - glm::dot(load_[k] + coupling_[k], x_[k]);
    if (grip_limit_[k] > 0.0) {
      const double len = glm::length(x_[k] - grip_anchor_[k]);
      const double limit = grip_limit_[k];
      e += kt * len <= limit ? 0.5 * kt * len * len : limit * len - 0.5 * limit * limit / kt;
    }
    const NodeContact& nc = node_contacts_[k];
    if (!nc.has_plane) continue;
    if (nc.active2) e += 0.5 * kc * second_gap(k) * second_gap(k);
    if (!nc.active) continue;
    const double phi = plane_gap(k);
    e += 0.5 * kc * phi * phi;
    const double limit = friction_limit_[k];
    if (limit <= 0.0) continue;
    const glm::dvec3 rel = x_[k] - nc.anchor;
    const double slip = glm::length(rel - nc.normal * glm::dot(nc.normal, rel));
    e += kt * slip <= limit ? 0.5 * kt * slip * slip : limit * slip - 0.5 * limit * limit / kt;
  }
  return e;
}

void Rod::seed_buckling() {
  // A perfectly straight rod pushed along its axis stays on the unstable straight branch;
  // real tools are never perfectly straight, so give the free nodes a tiny lateral offset.
  // A rod already bent by more than the offset would give (by the vessel, its own shape or an
  // earlier seed) needs none: seeding it again every compressed step only shakes it (and the
  // shaken rod then spends Newton iterations taking the offset back out).
  const std::size_t n = x_.size();
  for (std::size_t k = std::max(first_free_, std::size_t{1}); k + 1 < n; ++k) {
    if (glm::length(t_[k] - t_[k - 1]) * rest_[k] > settings_.buckling_seed_mm) return;
  }
  for (std::size_t k = first_free_; k < n; ++k) {
    const std::size_t e = std::min(k, n - 2);
    const double a = 0.7 * static_cast<double>(k);
    x_[k] += (m1_[e] * base::portable::cos(a) + m2_[e] * base::portable::sin(a)) * settings_.buckling_seed_mm;
  }
}

void Rod::limit_penetration() {
  const std::size_t n = x_.size();
  compressed_ = false;
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& nc = node_contacts_[k];
    if (nc.has_plane) {
      const double allowed = settings_.max_penetration_ratio * radius_[k];
      const double phi = plane_gap(k);
      if (phi > allowed) x_[k] -= nc.normal * (phi - allowed);
      if (phi > 0.0) nc.active = true;
      if (nc.has_second) {
        const double phi2 = second_gap(k);
        if (phi2 > allowed) x_[k] -= nc.normal2 * (phi2 - allowed);
        if (phi2 > 0.0) nc.active2 = true;
      }
    }
    if (k > 0 && glm::length(x_[k] - x_[k - 1]) < rest_[k - 1] * (1.0 - settings_.buckling_strain)) compressed_ = true;
  }
}

void Rod::update_frames() {
  const std::size_t n = x_.size();
  for (std::size_t k = first_edge(); k + 1 < n; ++k) {
    const glm::dvec3 e = x_[k + 1] - x_[k];
    const double len = glm::length(e);
    if (!(len > 1e-12)) continue;
    const glm::dvec3 t = e / len;
    glm::dvec3 d1 = transport(d1_[k], t_[k], t);
    d1 = d1 - t * glm::dot(d1, t);
    const double dl = glm::length(d1);
    d1_[k] = dl > 1e-9 ? d1 / dl : perpendicular_unit(t);
    t_[k] = t;
  }
  for (std::size_t i = first_ + 1; i + 1 < n; ++i) {
    const glm::dvec3 v = transport(d1_[i - 1], t_[i - 1], t_[i]);
    ref_twist_[i] = base::portable::atan2(glm::dot(glm::cross(v, d1_[i]), t_[i]), glm::dot(v, d1_[i]));
  }
}

// Thomas' forward and back substitution of tw_rhs_ (m unknowns) with the inverse pivots tw_inv_
// of the twist system (off[j] couples j-1 and j): the twist update, and the hand's Schur complement.
void Rod::twist_substitute(std::size_t m) {
  for (std::size_t j = 1; j < m; ++j) tw_rhs_[j] -= tw_off_[j] * tw_inv_[j - 1] * tw_rhs_[j - 1];
  tw_rhs_[m - 1] *= tw_inv_[m - 1];
  for (std::size_t j = m - 1; j-- > 0;) tw_rhs_[j] = (tw_rhs_[j] - tw_off_[j + 1] * tw_rhs_[j + 1]) * tw_inv_[j];
}

void Rod::solve_twist(double dt_s) {
  const std::size_t n = x_.size();
  const std::size_t ef = first_edge();  // first free edge; edge ef - 1 is clamped (unless free)
  const std::size_t m = n - 1 - ef;        // free edges
  auto material = [&](std::size_t e) {
    const glm::dvec3 d2 = glm::cross(t_[e], d1_[e]);
    const double c = base::portable::cos(theta_[e]);
    const double s = base::portable::sin(theta_[e]);
    m1_[e] = d1_[e] * c + d2 * s;
    m2_[e] = d2 * c - d1_[e] * s;
  };
  const double kt = settings_.contact_stiffness_mN_per_mm * settings_.stick_stiffness_ratio;
  if (m > 0 && first_free_ < n) {
    const int iterations = std::max(1, settings_.twist_iterations);
    for (int it = 0; it < iterations; ++it) {
      // The system is linear but for the pre-curve coupling and the friction's stick / slip
      // switch: without the one, and with every contact in the same regime after the update as
      // before it, the update solved it exactly and a further iteration would not move.
      bool linear = true;
      for (std::size_t j = 0; j < m; ++j) {
        const std::size_t e = ef + j;
        const double r = radius_[e + 1];
        const double c = solver_drag(e + 1) * r * r / dt_s + 1e-9;
        tw_diag_[j] = c;
        tw_off_[j] = 0.0;
        tw_rhs_[j] = c * (theta_[e] - theta_start_[e]);
      }
      // Twist at every vertex i between edges i-1 and i.
      for (std::size_t i = free_ ? 1 : ef; i + 1 < n; ++i) {
        const double c = gj_[i] / (i == ef && !free_ ? 0.5 * rest_[i] : voronoi_[i]);
        const double tau = theta_[i] - theta_[i - 1] + ref_twist_[i];
        const std::size_t j = i - ef;
        tw_diag_[j] += c;
        tw_rhs_[j] += c * tau;
        if (i - 1 >= ef) {
          tw_diag_[j - 1] += c;
          tw_rhs_[j - 1] -= c * tau;
          tw_off_[j] -= c;
        }
        if (kbar1_[i] != 0.0 || kbar2_[i] != 0.0) {
          // Pre-curved sections: the material curvature depends on the edge angles.
          linear = false;
          const glm::dvec3 a = x_[i] - x_[i - 1];
          const glm::dvec3 b = x_[i + 1] - x_[i];
          const double chi = std::max(glm::length(a) * glm::length(b) + glm::dot(a, b), 1e-12);
          const glm::dvec3 kb = glm::cross(a, b) * (2.0 / chi);
          const double w = 0.5 * (ei_[i] + ei_extra_[i]) / voronoi_[i];
          for (std::size_t e = i - 1; e <= i; ++e) {
            if (e < ef) continue;
            material(e);
            const double k1 = glm::dot(kb, m2_[e]);
            const double k2 = -glm::dot(kb, m1_[e]);
            // E = w/2 |k - kbar|^2 with dk1/dtheta = k2, dk2/dtheta = -k1.
            tw_rhs_[e - ef] += w * (kbar2_[i] * k1 - kbar1_[i] * k2);
            tw_diag_[e - ef] += w * std::max(0.0, kbar1_[i] * k1 + kbar2_[i] * k2);
          }
        }
      }
      // Torsional wall friction: stick spring with a slip limit.
      const auto regime = [&](std::size_t k, double& ktr, double& limit, double& d) -> std::uint8_t {
        const NodeContact& nc = node_contacts_[k];
        if (!nc.has_plane || spec_.friction <= 0.0) return 0;
        const double phi = glm::dot(nc.normal, x_[k] - nc.point) + radius_[k];
        if (phi <= 0.0) return 0;
        const double r = radius_[k];
        ktr = kt * r * r;
        limit = spec_.friction * settings_.contact_stiffness_mN_per_mm * phi * r;
        d = theta_[std::min(k, n - 2)] - nc.twist_anchor;
        if (ktr * std::abs(d) <= limit) return 1;  // stick
        return d > 0.0 ? 2 : 3;                    // slip either way
      };
      for (std::size_t k = first_free_; k < n; ++k) {
        double ktr = 0.0, limit = 0.0, d = 0.0;
        const std::uint8_t state = regime(k, ktr, limit, d);
        tw_regime_[k] = state;
        const std::size_t j = std::min(k, n - 2) - ef;
        if (state == 1) {
          tw_rhs_[j] += ktr * d;
          tw_diag_[j] += ktr;
        } else if (state != 0) {
          tw_rhs_[j] += state == 2 ? limit : -limit;
        }
      }
      // Thomas algorithm on the symmetric tridiagonal system (off[j] couples j-1 and j),
      // keeping the inverse pivots (the hand's Schur complement below reuses them).
      tw_inv_[0] = 1.0 / tw_diag_[0];
      for (std::size_t j = 1; j < m; ++j) tw_inv_[j] = 1.0 / (tw_diag_[j] - tw_off_[j] * tw_inv_[j - 1] * tw_off_[j]);
      twist_substitute(m);
      for (std::size_t j = 0; j < m; ++j) {
        const double step = tw_rhs_[j];
        if (!std::isfinite(step)) {
          linear = false;
          continue;
        }
        if (std::abs(step) > 0.5) linear = false;
        theta_[ef + j] -= std::clamp(step, -0.5, 0.5);
      }
      if (!linear || it + 1 == iterations) continue;
      bool same = true;
      for (std::size_t k = first_free_; k < n && same; ++k) {
        double ktr = 0.0, limit = 0.0, d = 0.0;
        same = regime(k, ktr, limit, d) == tw_regime_[k];
      }
      if (same) break;
    }
    if (free_) {
      law_.torsion_stiffness_mNmm_per_rad = 0.0;
      hand_torque_mNmm_ = 0.0;
      for (std::size_t e = first_; e + 1 < n; ++e) material(e);
      return;
    }
    // Torsional stiffness at the hand: Schur complement of the last system on the clamp.
    const double c0 = gj_[ef] / (0.5 * rest_[ef]);
    for (std::size_t j = 0; j < m; ++j) tw_rhs_[j] = j == 0 ? 1.0 : 0.0;
    twist_substitute(m);
    law_.torsion_stiffness_mNmm_per_rad = std::max(0.0, c0 - c0 * c0 * tw_rhs_[0]);
    const double tau0 = theta_[ef] - theta_[ef - 1] + ref_twist_[ef];
    // As for the force: the solver's twist damping above the physical drag stays out of the hand.
    double numerical = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
      const std::size_t e = ef + j;
      const double r = radius_[e + 1];
      numerical += (solver_drag(e + 1) - drag_per_mm_[e + 1] * voronoi_[e + 1]) * r * r / dt_s * (theta_[e] - theta_start_[e]);
    }
    hand_torque_mNmm_ = -c0 * tau0 - numerical;
  } else {
    law_.torsion_stiffness_mNmm_per_rad = 0.0;
    hand_torque_mNmm_ = 0.0;
  }
  for (std::size_t e = first_; e + 1 < n; ++e) material(e);
}

void Rod::finish_contacts() {
  const std::size_t n = x_.size();
  contacts_.clear();
  const double kc = settings_.contact_stiffness_mN_per_mm;
  const double kt = kc * settings_.stick_stiffness_ratio;
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& nc = node_contacts_[k];
    if (!nc.has_plane) continue;
    nc.normal_force2 = nc.has_second ? kc * std::max(0.0, second_gap(k)) : 0.0;
    if (nc.normal_force2 > 0.0) {
      RodContact second;
      second.node = static_cast<std::uint32_t>(k);
      second.point_mm = x_[k] + nc.normal2 * (radius_[k] - second_gap(k));
      second.normal = nc.normal2;
      second.normal_force_mN = nc.normal_force2;
      second.segment = nc.segment;
      contacts_.push_back(second);
    }
    const double phi = glm::dot(nc.normal, x_[k] - nc.point) + radius_[k];
    const std::size_t e = std::min(k, n - 2);
    if (phi <= 0.0) {
      nc.anchor = x_[k];
      nc.twist_anchor = theta_[e];
      nc.normal_force = 0.0;
      continue;
    }
    const double normal_force = kc * phi;
    const glm::dmat3 pt = glm::dmat3(1.0) - glm::outerProduct(nc.normal, nc.normal);
    const glm::dvec3 slip = pt * (x_[k] - nc.anchor);
    const double slip_len = glm::length(slip);
    const double limit = spec_.friction * normal_force;
    glm::dvec3 friction(0.0);
    if (kt * slip_len > limit && slip_len > 0.0) {
      const glm::dvec3 s = slip / slip_len;
      nc.anchor = x_[k] - s * (limit / kt);
      friction = -s * limit;
    } else {
      friction = -slip * kt;
    }
    const double r = radius_[k];
    const double ktr = kt * r * r;
    const double tlimit = limit * r;
    const double d = theta_[e] - nc.twist_anchor;
    if (ktr * std::abs(d) > tlimit) nc.twist_anchor = theta_[e] - (d > 0.0 ? tlimit : -tlimit) / ktr;
    nc.normal_force = normal_force;
    RodContact out;
    out.node = static_cast<std::uint32_t>(k);
    out.point_mm = x_[k] + nc.normal * (r - phi);
    out.normal = nc.normal;
    out.normal_force_mN = normal_force;
    out.friction_mN = friction;
    out.segment = nc.segment;
    contacts_.push_back(out);
  }
}

double Rod::edge_gap(const EdgeContact& c) const {
  const glm::dvec3 p = x_[c.edge] * (1.0 - c.s) + x_[c.edge + 1] * c.s;
  return c.offset_mm - glm::dot(c.normal, p);
}

void Rod::gather_obstacles(const RodObstacles& obstacles) {
  obstacles.gather(*this, edge_contacts_);
  for (std::size_t k = first_free_; k < x_.size(); ++k) gathered_at_[k] = x_[k];
  // Only edges with a free node can move away.
  std::erase_if(edge_contacts_, [&](const EdgeContact& c) {
    return c.edge + 1 >= x_.size() || c.edge + 1 < first_free_;
  });
}

bool Rod::finish_edge_contacts() {
  // Held to within the penetration limit, like the wall; the force is the penalty's.
  const double kc = settings_.contact_stiffness_mN_per_mm;
  bool pushed = false;
  for (EdgeContact& ec : edge_contacts_) {
    const double phi = edge_gap(ec);
    const double allowed = settings_.max_penetration_ratio * radius_[ec.edge];
    if (phi > allowed) {
      pushed = true;
      const glm::dvec3 push = ec.normal * (phi - allowed);
      if (ec.edge >= first_free_) x_[ec.edge] += push;
      if (ec.edge + 1 >= first_free_) x_[ec.edge + 1] += push;
    }
    ec.force_mN = kc * std::max(0.0, std::min(phi, allowed));
  }
  // Gripping nodes that were pulled beyond the limit slip: the anchor follows.
  const double kg = kc * settings_.stick_stiffness_ratio;
  for (std::size_t k = first_free_; k < x_.size(); ++k) {
    if (grip_limit_[k] <= 0.0) continue;
    const glm::dvec3 rel = x_[k] - grip_anchor_[k];
    const double len = glm::length(rel);
    if (kg * len > grip_limit_[k]) grip_anchor_[k] = x_[k] - rel * (grip_limit_[k] / (kg * len));
  }
  return pushed;
}

void Rod::add_coupling_load(std::size_t node, const glm::dvec3& force_mN) {
  if (node < coupling_.size() && std::isfinite(force_mN.x + force_mN.y + force_mN.z)) {
    coupling_[node] += force_mN;
    coupling_set_.add(node);
  }
}

void Rod::set_grip(std::size_t node, double limit_mN) {
  if (node >= grip_limit_.size()) return;
  const double limit = std::isfinite(limit_mN) ? std::max(0.0, limit_mN) : 0.0;
  if (limit > 0.0 && grip_limit_[node] <= 0.0) grip_anchor_[node] = x_[node];
  grip_limit_[node] = limit;
}

void Rod::clear_coupling_loads() {
  const std::size_t size = coupling_.size();
  std::fill(coupling_.begin() + static_cast<std::ptrdiff_t>(coupling_set_.begin_in(size)),
            coupling_.begin() + static_cast<std::ptrdiff_t>(coupling_set_.end_in(size)), glm::dvec3(0.0));
  coupling_set_.clear();
}

glm::dvec3 Rod::clamp_force_mN() const { return clamp_force_; }

void Rod::forget_wall() {
  for (NodeContact& c : node_contacts_) c = NodeContact{};
}

Rod Rod::split_distal(double length_mm) {
  Rod coil;
  const std::size_t n = x_.size();
  // The detachment node: the station length_mm from the tip.
  std::size_t k0 = n;
  for (std::size_t k = 0; k < n; ++k) {
    if (std::abs(from_tip_[k] - length_mm) < 1e-9) k0 = k;
  }
  if (k0 + 2 >= n || k0 < 2) return coil;  // not a node, or too short to stand alone
  const auto tail = [&](const auto& v, std::size_t from) {
    using V = std::decay_t<decltype(v)>;
    return V(v.begin() + static_cast<std::ptrdiff_t>(from), v.end());
  };
  coil.spec_ = spec_;
  coil.spec_.name = spec_.name + " (detached)";
  coil.spec_.detach_mm = 0.0;
  coil.spec_.inside.clear();
  // The coil's sections: the distal length_mm of the tool's.
  std::vector<ToolSection> distal;
  double left = length_mm;
  for (auto it = spec_.sections.rbegin(); it != spec_.sections.rend() && left > 1e-9; ++it) {
    ToolSection part = *it;
    part.length_mm = std::min(part.length_mm, left);
    left -= part.length_mm;
    distal.insert(distal.begin(), part);
  }
  coil.spec_.sections = distal;
  coil.settings_ = settings_;
  coil.length_mm_ = length_mm;
  coil.free_ = true;
  coil.from_tip_ = tail(from_tip_, k0);
  coil.radius_ = tail(radius_, k0);
  coil.inner_radius_ = tail(inner_radius_, k0);
  coil.ei_ = tail(ei_, k0);
  coil.ei_extra_.assign(n - k0, 0.0);
  coil.gj_ = tail(gj_, k0);
  coil.voronoi_ = tail(voronoi_, k0);
  coil.drag_per_mm_ = tail(drag_per_mm_, k0);
  coil.kbar1_ = tail(kbar1_, k0);
  coil.kbar2_ = tail(kbar2_, k0);
  coil.kturn1_ = tail(kturn1_, k0);
  coil.kturn2_ = tail(kturn2_, k0);
  coil.x_ = tail(x_, k0);
  coil.x_start_ = coil.x_;
  coil.x_pred_ = coil.x_;
  coil.load_.assign(n - k0, glm::dvec3(0.0));
  coil.coupling_.assign(n - k0, glm::dvec3(0.0));
  coil.grip_anchor_.assign(n - k0, glm::dvec3(0.0));
  coil.grip_limit_.assign(n - k0, 0.0);
  coil.node_contacts_ = tail(node_contacts_, k0);
  coil.rest_ = tail(rest_, k0);
  coil.theta_ = tail(theta_, k0);
  coil.theta_start_ = coil.theta_;
  coil.ref_twist_ = tail(ref_twist_, k0);
  coil.t_ = tail(t_, k0);
  coil.d1_ = tail(d1_, k0);
  coil.m1_ = tail(m1_, k0);
  coil.m2_ = tail(m2_, k0);
  // The new ends: half an edge each, no bending at the end vertex.
  coil.voronoi_.front() = 0.5 * coil.rest_.front();
  coil.kbar1_.front() = coil.kbar2_.front() = coil.kturn1_.front() = coil.kturn2_.front() = 0.0;
  coil.insertion_mm_ = insertion_mm_;
  coil.rotation_rad_ = rotation_rad_;
  coil.entry_ = entry_;
  coil.dir_ = dir_;
  coil.first_ = 0;
  coil.first_free_ = 0;
  coil.size_scratch();

  // This rod keeps nodes [0, k0]: its tip is now the detachment node.
  const std::size_t m = k0 + 1;
  const auto head = [&](auto& v, std::size_t count) { v.resize(count); };
  for (auto* v : {&from_tip_, &radius_, &inner_radius_, &ei_, &ei_extra_, &gj_, &voronoi_, &drag_per_mm_, &kbar1_, &kbar2_,
                  &kturn1_, &kturn2_}) head(*v, m);
  for (auto* v : {&x_, &x_start_, &x_pred_, &load_, &coupling_, &grip_anchor_}) head(*v, m);
  head(grip_limit_, m);
  head(node_contacts_, m);
  for (auto* v : {&rest_, &theta_, &theta_start_}) head(*v, m - 1);
  head(ref_twist_, m);
  for (auto* v : {&t_, &d1_, &m1_, &m2_}) head(*v, m - 1);
  for (double& d : from_tip_) d -= length_mm;
  voronoi_.back() = 0.5 * rest_.back();
  kbar1_.back() = kbar2_.back() = kturn1_.back() = kturn2_.back() = 0.0;
  insertion_mm_ = std::max(0.0, insertion_mm_ - length_mm);
  stepped_insertion_mm_ = std::max(0.0, stepped_insertion_mm_ - length_mm);
  length_mm_ -= length_mm;
  left = length_mm;
  while (!spec_.sections.empty() && left > 1e-9) {
    ToolSection& last = spec_.sections.back();
    if (last.length_mm <= left + 1e-9) {
      left -= last.length_mm;
      spec_.sections.pop_back();
    } else {
      last.length_mm -= left;
      left = 0.0;
    }
  }
  spec_.detach_mm = 0.0;
  contacts_.clear();
  edge_contacts_.clear();
  update_window();
  return coil;
}

void Rod::compute_force_law(double dt_s) {
  const std::size_t n = x_.size();
  law_.insertion0_mm = insertion_mm_;
  law_.rotation0_rad = rotation_rad_;
  // The hand feels the physical drag only: the solver's floor above it (numerical damping) is
  // taken back out of the force below, and the law renders the physical damping.
  double drag_total = 0.0;       // what the solver used
  double physical_total = 0.0;
  double rot_physical_total = 0.0;
  glm::dvec3 numerical_drag(0.0);
  for (std::size_t k = first_free_; k < n; ++k) {
    const double physical = drag_per_mm_[k] * voronoi_[k];
    drag_total += solver_drag(k);
    physical_total += physical;
    rot_physical_total += physical * radius_[k] * radius_[k];
    numerical_drag += (solver_drag(k) - physical) / dt_s * (x_[k] - x_start_[k]);
  }
  law_.damping_mN_s_per_mm = physical_total;
  law_.torsion_damping_mNmm_s_per_rad = rot_physical_total;
  law_.torque0_mNmm = hand_torque_mNmm_;
  clamp_force_ = glm::dvec3(0.0);
  if (first_free_ >= n || free_) {
    hand_force_mN_ = 0.0;
    law_.force0_mN = 0.0;
    law_.stiffness_mN_per_mm = 0.0;
    return;
  }
  // Axial force on the clamp: the energy gradient on the outside nodes along the entry.
  for (std::size_t k = first_; k < first_free_; ++k) {
    const std::size_t d = 3 * (k - first_);
    clamp_force_ += glm::dvec3(grad_[d], grad_[d + 1], grad_[d + 2]);
  }
  // The numerical damping on the free nodes reaches the clamp through the rod: out of the hand.
  const double force = glm::dot(clamp_force_, dir_) - glm::dot(numerical_drag, dir_);
  hand_force_mN_ = force;
  law_.force0_mN = force;
  // Stiffness: Schur complement of the (factored) free block on a unit insertion.
  const std::size_t dofs = 3 * (n - first_);
  const std::size_t free0 = 3 * (first_free_ - first_);
  std::fill(work_.begin(), work_.begin() + static_cast<std::ptrdiff_t>(dofs), 0.0);
  for (std::size_t k = first_; k < first_free_; ++k) {
    const std::size_t d = 3 * (k - first_);
    work_[d] = dir_.x;
    work_[d + 1] = dir_.y;
    work_[d + 2] = dir_.z;
  }
  std::fill(delta_.begin(), delta_.begin() + static_cast<std::ptrdiff_t>(dofs), 0.0);
  matrix_->multiply_add(work_.data(), delta_.data(), 0, dofs, 0, free0);  // K[:, p] d
  double kpp = 0.0;
  for (std::size_t i = 0; i < free0; ++i) kpp += work_[i] * delta_[i];
  double coupling = 0.0;
  for (std::size_t i = free0; i < dofs; ++i) work_[i] = delta_[i];
  matrix_->solve(work_.data());
  for (std::size_t i = free0; i < dofs; ++i) coupling += delta_[i] * work_[i];
  const double k_with_drag = kpp - coupling;
  law_.stiffness_mN_per_mm = std::max(0.0, k_with_drag - drag_total / dt_s);
}

}  // namespace cathbox::tool

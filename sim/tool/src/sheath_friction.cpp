#include "tool/sheath_friction.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "base/portable_math.hpp"

namespace cathbox::tool {

namespace {
constexpr double kMilli = 1000.0;  // N -> mN

glm::dvec3 unit_or(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double l = glm::length(v);
  return l > 1e-12 ? v / l : fallback;
}
}  // namespace

void SheathFriction::reset() {
  slide_ = anchor_ = turn_ = turn_anchor_ = 0.0;
}

SheathFriction::Result SheathFriction::update(double slide_mm, double turn_rad, double distal_force_mN,
                                              const std::vector<SheathVertex>& path,
                                              double anchor_stiffness_mN_per_mm) {
  Result out;
  out.anchor_mN_per_mm = anchor_stiffness_mN_per_mm;
  const std::size_t m = path.size();
  normal_fwd_.assign(m, 0.0);
  normal_back_.assign(m, 0.0);
  axial_.assign(m + 1, distal_force_mN);
  turning_.assign(m, 0.0);
  reaction_.assign(m, glm::dvec3(0.0));
  slide_ += std::isfinite(slide_mm) ? slide_mm : 0.0;
  turn_ += std::isfinite(turn_rad) ? turn_rad : 0.0;
  if (m < 3) {
    anchor_ = slide_;
    turn_anchor_ = turn_;
    out.force_mN = 0.0;
    return out;
  }
  measure_turning(path);
  const auto [t_fwd, t_back] = capstan_normals(path, distal_force_mN);
  out.force_limit_fwd_mN = t_fwd - distal_force_mN;
  out.force_limit_back_mN = t_back - distal_force_mN;
  const double k = std::max(1e-9, anchor_stiffness_mN_per_mm);
  stick_slide(k, out);
  const double torque_limit = distribute_friction(path, distal_force_mN, out);
  out.torque_limit_mNmm = torque_limit;
  const double r_mean = path.front().inner_radius_mm;
  stick_twist(k * r_mean * r_mean, torque_limit, out);
  return out;
}

// Turning angle and bending push at the vertices (index 0 is distal), a fading vertex's
// neighbourhood mixed between the path without it and with it by its weight.
void SheathFriction::measure_turning(const std::vector<SheathVertex>& path) {
  const std::size_t m = path.size();
  const auto fading = [&](std::size_t j) { return path[j].weight < 1.0; };
  for (std::vector<double>* v : {&turning_, &bending_, &curvature_, &turning_without_, &bending_without_}) v->resize(m);
  measure_on(path, false, 0, m, turning_, bending_);
  // The vertices that read a fading vertex f are f - 2 ... f + 2; a run [lo, hi) of them (runs that
  // touch merged) is measured again without the fading vertices, on the vertices from the first
  // one kept below the run to the second one kept above it (what its turning and bending read):
  // the same values as the whole path measured without them, for a few vertices' work.
  for (std::size_t j = 0; j < m;) {
    std::size_t f = j;
    while (f < m && !fading(f)) ++f;
    if (f == m) break;
    const std::size_t lo = f >= 2 ? f - 2 : 0;
    std::size_t hi = std::min(m, f + 3);
    for (std::size_t g = f + 1; g < m && g <= hi + 2; ++g) {
      if (fading(g)) hi = std::min(m, g + 3);
    }
    std::size_t first = lo;
    for (std::size_t k = lo; k-- > 0;) {
      if (!fading(k)) {
        first = k;
        break;
      }
    }
    std::size_t last = hi;
    for (std::size_t kept = 0; last < m && kept < 2; ++last) kept += fading(last) ? 0 : 1;
    measure_on(path, true, first, last, turning_without_, bending_without_);
    for (std::size_t i = lo; i < hi; ++i) {
      double w = 1.0;
      for (std::size_t g = i >= 2 ? i - 2 : 0; g <= i + 2 && g < m; ++g) w = std::min(w, std::clamp(path[g].weight, 0.0, 1.0));
      turning_[i] = w * turning_[i] + (1.0 - w) * turning_without_[i];
      bending_[i] = w * bending_[i] + (1.0 - w) * bending_without_[i];
    }
    j = hi;
  }
}

// Turning, curvature and the bending push on the path's vertices [first, last), or on those of
// them not fading in (the others get none).
void SheathFriction::measure_on(const std::vector<SheathVertex>& path, bool skip_fading, std::size_t first,
                                std::size_t last, std::vector<double>& turning, std::vector<double>& bending) {
  for (std::vector<double>* v : {&turning, &bending, &curvature_}) std::fill(v->begin() + first, v->begin() + last, 0.0);
  active_.clear();
  for (std::size_t j = first; j < last; ++j) {
    if (!skip_fading || path[j].weight >= 1.0) active_.push_back(j);
  }
  const std::size_t r = active_.size();
  for (std::size_t i = 1; i + 1 < r; ++i) {
    const std::size_t j = active_[i];
    const glm::dvec3 a = path[j].point_mm - path[active_[i + 1]].point_mm;  // distal direction, proximal edge
    const glm::dvec3 b = path[active_[i - 1]].point_mm - path[j].point_mm;  // distal edge
    const double la = glm::length(a);
    const double lb = glm::length(b);
    if (!(la > 1e-9) || !(lb > 1e-9)) continue;
    const double c = std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0);
    turning[j] = base::portable::acos(c) * std::clamp(path[j].coverage, 0.0, 1.0);
    curvature_[j] = turning[j] / (0.5 * (la + lb));
  }
  for (std::size_t i = 0; i + 1 < r; ++i) {
    const std::size_t j = active_[i];
    const std::size_t next = active_[i + 1];
    // The shear the lumen holds: the change of the bending moment EI k over the edge.
    const double dm = std::abs(path[j].inner_ei_Nmm2 * curvature_[j] - path[next].inner_ei_Nmm2 * curvature_[next]);
    if (!(dm > 0.0)) continue;
    const double k = std::max({curvature_[j], curvature_[next], 1e-9});
    const double h = glm::length(path[j].point_mm - path[next].point_mm);
    const double l = std::max(h, 2.0 * std::sqrt(2.0 * std::max(0.0, path[j].clearance_mm) / k));
    bending[j] = kMilli * dm / l;
  }
}

// Normal forces for sliding forwards and backwards (capstan on the running axial force).
std::pair<double, double> SheathFriction::capstan_normals(const std::vector<SheathVertex>& path, double distal_force_mN) {
  const std::size_t m = path.size();
  double t_fwd = distal_force_mN;
  double t_back = distal_force_mN;
  for (std::size_t j = 0; j < m; ++j) {
    normal_fwd_[j] = std::abs(t_fwd) * turning_[j] + bending_[j];
    normal_back_[j] = std::abs(t_back) * turning_[j] + bending_[j];
    t_fwd += path[j].mu * normal_fwd_[j];
    t_back -= path[j].mu * normal_back_[j];
  }
  return {t_fwd, t_back};
}

// Stick spring with slip at the limits.
void SheathFriction::stick_slide(double k, Result& out) {
  double f = k * (slide_ - anchor_);
  out.sticking = true;
  if (f > out.force_limit_fwd_mN) {
    f = out.force_limit_fwd_mN;
    anchor_ = slide_ - f / k;
    out.sticking = false;
  } else if (f < out.force_limit_back_mN) {
    f = out.force_limit_back_mN;
    anchor_ = slide_ - f / k;
    out.sticking = false;
  }
  out.force_mN = f;
}

// The axial force profile and the normal forces that go with the friction actually acting.
double SheathFriction::distribute_friction(const std::vector<SheathVertex>& path, double distal_force_mN, const Result& out) {
  const std::size_t m = path.size();
  const double f = out.force_mN;
  const std::vector<double>& normal = f >= 0.0 ? normal_fwd_ : normal_back_;
  const double limit = f >= 0.0 ? out.force_limit_fwd_mN : out.force_limit_back_mN;
  const double share = std::abs(limit) > 1e-12 ? f / limit : 0.0;
  double t = distal_force_mN;
  double torque_limit = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    axial_[j] = t;
    const double fj = (f >= 0.0 ? 1.0 : -1.0) * path[j].mu * normal[j] * share;  // resists insertion
    torque_limit += path[j].mu * (std::abs(t) * turning_[j] + bending_[j]) * path[j].inner_radius_mm;
    t += fj;
    // Reaction on the holder: the friction drags it along, and where the path turns the axial
    // force t presses on the lumen with t (a - b), a and b the directions of the edges in and
    // out (a compressed tool pushes the bend outwards, one in tension pulls it in).
    const glm::dvec3 distal =
        j > 0 ? unit_or(path[j - 1].point_mm - path[j].point_mm, glm::dvec3(0.0))
              : unit_or(path[0].point_mm - path[1].point_mm, glm::dvec3(0.0));
    reaction_[j] = distal * fj;
    if (bend_reaction_ && j > 0 && j + 1 < m) {
      const glm::dvec3 in = unit_or(path[j].point_mm - path[j + 1].point_mm, glm::dvec3(0.0));
      reaction_[j] += t * std::clamp(path[j].coverage, 0.0, 1.0) * (in - distal);
    }
  }
  axial_[m] = t;
  return torque_limit;
}

// Twist spring with slip at the friction torque limit.
void SheathFriction::stick_twist(double kt, double torque_limit, Result& out) {
  double tau = kt * (turn_ - turn_anchor_);
  out.twist_sticking = true;
  if (std::abs(tau) > torque_limit) {
    tau = tau > 0.0 ? torque_limit : -torque_limit;
    turn_anchor_ = turn_ - tau / std::max(1e-12, kt);
    out.twist_sticking = false;
  }
  out.torque_mNmm = tau;
}

}  // namespace cathbox::tool

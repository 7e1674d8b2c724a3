#include "tool/balloon.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::tool {

Balloon::Balloon(const BalloonSpec& spec, double shaft_diameter_mm)
    : spec_(spec), shaft_diameter_mm_(shaft_diameter_mm) {
  if (!spec_.pressure_atm.empty() && spec_.pressure_atm.front() > 0.0) {
    inflated_above_atm_ = std::min(kInflatedAbove_atm, spec_.pressure_atm.front());
  }
}

double Balloon::diameter_at(double p) const {
  const auto& ps = spec_.pressure_atm;
  const auto& ds = spec_.diameter_mm;
  if (ps.empty() || ps.size() != ds.size() || !(p > 0.0)) return shaft_diameter_mm_;
  if (p <= ps.front()) {
    // Unfolding from the shaft to the chart's first point.
    const double f = ps.front() > 0.0 ? p / ps.front() : 1.0;
    return shaft_diameter_mm_ + (ds.front() - shaft_diameter_mm_) * f;
  }
  for (std::size_t i = 1; i < ps.size(); ++i) {
    if (p <= ps[i]) return ds[i - 1] + (ds[i] - ds[i - 1]) * (p - ps[i - 1]) / (ps[i] - ps[i - 1]);
  }
  if (ps.size() < 2) return ds.back();
  const std::size_t n = ps.size();
  const double slope = (ds[n - 1] - ds[n - 2]) / (ps[n - 1] - ps[n - 2]);
  return ds[n - 1] + slope * (p - ps[n - 1]);
}

double Balloon::volume_at(double p) const {
  const double d = diameter_at(p);
  const double shaft = shaft_diameter_mm_;
  // Fluid volume: the balloon's cylinder less the shaft it is wrapped around, in ml (1000 mm^3).
  return std::max(0.0, M_PI / 4.0 * (d * d - shaft * shaft) * spec_.length_mm) / 1000.0;
}

double Balloon::pressure_for_volume(double v) const {
  if (!(v > 0.0)) return 0.0;
  double lo = 0.0, hi = kMaxPressure_atm;
  if (volume_at(hi) <= v) return hi;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (volume_at(mid) < v ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

void Balloon::set_target_pressure(double p) {
  if (std::isfinite(p)) target_atm_ = std::clamp(p, 0.0, kMaxPressure_atm);
}

void Balloon::set_target_volume(double v) {
  if (std::isfinite(v)) target_atm_ = pressure_for_volume(v);
}

void Balloon::step(double dt_s) {
  if (!(dt_s > 0.0)) return;
  const double d = target_atm_ - pressure_atm_;
  const double rate = d >= 0.0 ? kInflateRate_atm_s : kDeflateRate_atm_s;
  pressure_atm_ = std::abs(d) <= rate * dt_s ? target_atm_ : pressure_atm_ + (d > 0.0 ? rate : -rate) * dt_s;
  const bool now = inflated();
  if (now && !was_inflated_) ++inflations_;
  was_inflated_ = now;
  if (now) inflated_time_s_ += dt_s;
  max_pressure_atm_ = std::max(max_pressure_atm_, pressure_atm_);
  if (pressure_atm_ > spec_.rated_burst_atm + 1e-9) over_rated_burst_ = true;
}

}  // namespace cathbox::tool

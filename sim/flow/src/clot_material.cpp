#include "flow/clot_material.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace cathbox::flow {
namespace {

// Floor of the linear composition model: the regression of Boodt et al. (Stroke 2021) covers
// the specimens' range; extrapolated to a nearly pure red-cell clot it would go negative.
constexpr double kEt75Floor_kPa = 0.1 * kMedianEt75_kPa;
constexpr double kStrainAt_Et = 0.75;
constexpr double kMaxStrain = 0.95;

// Friction of clot analogues on arterial wall (Elkhayyat et al., J Biomech 2024): static
// coefficients at 0 / 20 / 40 % haematocrit; kinetic at 20 / 40 %; the kinetic coefficient of a
// pure fibrin clot (0 %) is not reported and is taken as the 20 % value times the static ratio
// 1.49 / 0.57 (fibrin-rich clots 3-4 x higher).
constexpr std::array<double, 3> kHaematocrit{0.0, 20.0, 40.0};
constexpr std::array<double, 3> kStatic{1.49, 0.57, 0.46};
constexpr std::array<double, 3> kKinetic{0.26 * 1.49 / 0.57, 0.26, 0.23};

double interpolate(const std::array<double, 3>& ys, double h) {
  h = std::clamp(h, kHaematocrit.front(), kHaematocrit.back());
  const std::size_t i = h <= kHaematocrit[1] ? 0 : 1;
  const double t = (h - kHaematocrit[i]) / (kHaematocrit[i + 1] - kHaematocrit[i]);
  return ys[i] + t * (ys[i + 1] - ys[i]);
}

}  // namespace

const char* check_composition(const ClotComposition& c) {
  const auto percent = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 100.0; };
  if (!percent(c.red_cell_percent)) return "clot red cells must be a percentage in [0, 100]";
  if (!percent(c.fibrin_platelet_percent)) return "clot fibrin/platelets must be a percentage in [0, 100]";
  if (c.red_cell_percent + c.fibrin_platelet_percent > 100.0 + 1e-9) return "clot red cells + fibrin/platelets exceed 100 %";
  return "";
}

double clot_et75_kPa(const ClotComposition& c) {
  const double e = kMedianEt75_kPa +
                   kEt75PerPercent_kPa * (c.fibrin_platelet_percent - kReferenceComposition.fibrin_platelet_percent) -
                   kEt75PerPercent_kPa * (c.red_cell_percent - kReferenceComposition.red_cell_percent);
  return std::max(e, kEt75Floor_kPa);
}

ClotCompressionLaw::ClotCompressionLaw(const ClotComposition& c)
    : et75_kPa_(clot_et75_kPa(c)), a_kPa_(0.0), b_(std::log(kStrainStiffeningRatio) / kStrainAt_Et) {
  // tangent(e) = A B exp(B e); tangent(0.75) = Et75.
  a_kPa_ = et75_kPa_ / (b_ * std::exp(b_ * kStrainAt_Et));
}

double ClotCompressionLaw::stress_kPa(double strain) const {
  const double e = std::clamp(strain, 0.0, kMaxStrain);
  return a_kPa_ * std::expm1(b_ * e);
}

double ClotCompressionLaw::tangent_kPa(double strain) const {
  const double e = std::clamp(strain, 0.0, kMaxStrain);
  return a_kPa_ * b_ * std::exp(b_ * e);
}

double ClotCompressionLaw::force_N(double strain, double area_mm2) const {
  return stress_kPa(strain) * 1e3 * area_mm2 * 1e-6;  // kPa -> Pa, mm^2 -> m^2
}

double equivalent_haematocrit_percent(const ClotComposition& c) {
  // Piecewise linear through (0 % red cells, 0 %), (45 %, 20 %), (80 %, 40 %).
  const double r = std::clamp(c.red_cell_percent, 0.0, 100.0);
  if (r <= 45.0) return 20.0 * r / 45.0;
  return std::min(40.0, 20.0 + 20.0 * (r - 45.0) / 35.0);
}

ClotFriction clot_wall_friction(const ClotComposition& c) {
  const double h = equivalent_haematocrit_percent(c);
  return {interpolate(kStatic, h), interpolate(kKinetic, h)};
}

}  // namespace cathbox::flow

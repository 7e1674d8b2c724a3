#include "tool/valve_friction.hpp"

#include <cmath>

namespace cathbox::tool {
namespace {

// One elastic-plastic anchor: the spring force, and the anchor dragged along past the limit.
double anchor_force(double x, double& anchor, double k, double limit, bool& sticking) {
  const double f = k * (x - anchor);
  sticking = std::abs(f) <= limit;
  if (sticking) return f;
  const double s = f > 0.0 ? 1.0 : -1.0;
  anchor = x - s * limit / k;
  return s * limit;
}

}  // namespace

ValveFriction::Result ValveFriction::update(double position_mm, double angle_rad, bool engaged, double limit_mN,
                                            double radius_mm, double anchor_stiffness_mN_per_mm) {
  Result r;
  if (!engaged || !(limit_mN > 0.0) || !(anchor_stiffness_mN_per_mm > 0.0)) {
    anchor_mm_ = position_mm;
    anchor_rad_ = angle_rad;
    return r;
  }
  r.force_mN = anchor_force(position_mm, anchor_mm_, anchor_stiffness_mN_per_mm, limit_mN, r.sticking);
  const double k_turn = anchor_stiffness_mN_per_mm * radius_mm * radius_mm;
  if (k_turn > 0.0) r.torque_mNmm = anchor_force(angle_rad, anchor_rad_, k_turn, limit_mN * radius_mm, r.twist_sticking);
  return r;
}

}  // namespace cathbox::tool

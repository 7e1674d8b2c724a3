#include "device/force_law_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace cathbox::device {
namespace {

std::int32_t clamp_i32(double v) {
  if (!(v == v)) return 0;  // NaN
  return static_cast<std::int32_t>(std::clamp(std::llround(std::clamp(v, -1e18, 1e18)),
                                              static_cast<long long>(INT32_MIN), static_cast<long long>(INT32_MAX)));
}

}  // namespace

cbx_command_report force_law_command(const base::ForceLaw& law, std::uint8_t mode) {
  // 1 mN mm = 1 uN m.
  cbx_command_report c{};
  c.mode = mode;
  c.insertion.offset = clamp_i32(-law.force0_mN);
  c.insertion.pos0 = clamp_i32(law.insertion0_mm * 1000.0);
  c.insertion.stiffness = clamp_i32(std::max(0.0, law.stiffness_mN_per_mm) * 1000.0);
  c.insertion.damping = clamp_i32(std::max(0.0, law.damping_mN_s_per_mm) * 1000.0);
  c.insertion.out_min = INT32_MIN;
  c.insertion.out_max = INT32_MAX;
  c.rotation.offset = clamp_i32(-law.torque0_mNmm);
  c.rotation.pos0 = clamp_i32(law.rotation0_rad * 1e6);
  c.rotation.stiffness = clamp_i32(std::max(0.0, law.torsion_stiffness_mNmm_per_rad));
  c.rotation.damping = clamp_i32(std::max(0.0, law.torsion_damping_mNmm_s_per_rad));
  c.rotation.out_min = INT32_MIN;
  c.rotation.out_max = INT32_MAX;
  return c;
}

cbx_command_report force_law_command(const base::ForceLaw& law, std::uint8_t mode, double out_min_mN,
                                     double out_max_mN) {
  cbx_command_report c = force_law_command(law, mode);
  c.insertion.out_min = clamp_i32(std::min(out_min_mN, out_max_mN));
  c.insertion.out_max = clamp_i32(std::max(out_min_mN, out_max_mN));
  return c;
}

cbx_command_report outputs_off_command() {
  cbx_command_report c{};
  c.mode = CBX_MODE_OFF;
  return c;
}

}  // namespace cathbox::device

#include "emu/box_model.hpp"

#include <cmath>

namespace cathbox::emu {

BoxModel::BoxModel() {
  // Insertion: a 12 mm roller with a 1024-line encoder (x4): 4096 counts per 37.7 mm.
  params_[0].counts_per_unit = 4096.0 / (3.14159265358979 * 0.012);
  // Rotation: a collet with a 1024-line encoder (x4), geared 1:1; small inertia and torques.
  params_[1].mass = 2e-5;
  params_[1].hand_stiffness = 0.5;
  params_[1].hand_damping = 0.01;
  params_[1].friction_damping = 2e-3;
  params_[1].full_scale = 0.05;
  params_[1].counts_per_unit = 4096.0 / (2.0 * 3.14159265358979);
}

void BoxModel::set_script(int axis, HandScript script, uint64_t start_us) {
  const auto a = static_cast<size_t>(axis);
  script_[a] = std::move(script);
  script_start_us_[a] = start_us;
  state_[a].target = state_[a].pos;
}

int16_t BoxModel::current_mA(int axis, int16_t drive) const {
  return static_cast<int16_t>(std::lround(params_[static_cast<size_t>(axis)].full_scale_current_mA * drive / 1000.0));
}

void BoxModel::step(double dt_s, uint64_t now_us, const std::array<int16_t, 2>& drive, std::array<int64_t, 2>& steps) {
  for (size_t a = 0; a < 2; ++a) {
    const AxisParams& p = params_[a];
    AxisState& s = state_[a];
    const uint64_t t = now_us >= script_start_us_[a] ? now_us - script_start_us_[a] : 0;
    const HandSegment seg = script_[a].at(t);
    switch (seg.mode) {
      case HandMode::kVelocity:
        s.target += seg.value * dt_s;
        s.hand_force = p.hand_stiffness * (s.target - s.pos) + p.hand_damping * (seg.value - s.vel);
        break;
      case HandMode::kForce:
        s.hand_force = seg.value;
        s.target = s.pos;
        break;
      case HandMode::kFree:
        s.hand_force = 0;
        s.target = s.pos;
        break;
    }
    const double level = drive[a] / 1000.0;
    double v = s.vel + (s.hand_force - p.friction_damping * s.vel) * dt_s / p.mass;
    if (p.motor) {
      s.actuator_force = level * p.full_scale;
      v += s.actuator_force * dt_s / p.mass;
    } else {
      // Brake: a friction force of up to |level| * full scale against the motion; it stops
      // (and holds) the tool when the impulse it can give exceeds the momentum.
      const double dv_max = std::fabs(level) * p.full_scale * dt_s / p.mass;
      if (std::fabs(v) <= dv_max) {
        s.actuator_force = -v * p.mass / dt_s;
        v = 0;
      } else {
        s.actuator_force = -std::copysign(std::fabs(level) * p.full_scale, v);
        v -= std::copysign(dv_max, v);
      }
    }
    s.vel = v;
    s.pos += v * dt_s;
    const auto count = static_cast<int64_t>(std::floor(s.pos * p.counts_per_unit));
    steps[a] = count - s.count;
    s.count = count;
  }
}

}  // namespace cathbox::emu

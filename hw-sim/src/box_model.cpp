#include "emu/box_model.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::emu {

BoxModel::BoxModel() {
  // Insertion: a 12 mm roller with a 1024-line encoder (x4): 4096 counts per 37.7 mm.
  params_[0].counts_per_unit = 4096.0 / (3.14159265358979 * 0.012);
  params_[0].travel = kToolLength;
  // Rotation: a collet with a 1024-line encoder (x4), geared 1:1; small inertia and torques.
  params_[1].mass = 1.6e-5;
  params_[1].tool_mass = 4e-6;
  params_[1].hand_stiffness = 0.5;
  params_[1].hand_damping = 0.01;
  params_[1].friction_damping = 2e-3;
  params_[1].friction_coulomb = 1e-3;
  params_[1].full_scale = 0.05;
  params_[1].counts_per_unit = 4096.0 / (2.0 * 3.14159265358979);
}

void BoxModel::set_script(int axis, HandScript script, uint64_t start_us) {
  const auto a = static_cast<size_t>(axis);
  script_[a] = std::move(script);
  script_start_us_[a] = start_us;
  state_[a].target = state_[a].tool_pos;
}

int16_t BoxModel::current_mA(int axis, int16_t drive) const {
  return static_cast<int16_t>(std::lround(params_[static_cast<size_t>(axis)].full_scale_current_mA * drive / 1000.0));
}

void BoxModel::hand(size_t a, uint64_t now_us, double dt_s) {
  const AxisParams& p = params_[a];
  AxisState& s = state_[a];
  const uint64_t t = now_us >= script_start_us_[a] ? now_us - script_start_us_[a] : 0;
  const HandSegment seg = script_[a].at(t);
  const bool entering = seg.mode != mode_[a];
  mode_[a] = seg.mode;
  switch (seg.mode) {
    case HandMode::kVelocity:
      s.target += seg.value * dt_s;
      s.hand_force = p.hand_stiffness * (s.target - s.tool_pos) + p.hand_damping * (seg.value - s.tool_vel);
      break;
    case HandMode::kForce:
      if (p.hand_impedance_in_force_mode) {
        // The arm holds still where the push began; the finger presses through its grip.
        if (entering) s.target = s.tool_pos;
        s.hand_force = seg.value + p.hand_stiffness * (s.target - s.tool_pos) - p.hand_damping * s.tool_vel;
      } else {
        s.hand_force = seg.value;
        s.target = s.tool_pos;
      }
      break;
    case HandMode::kFree:
      s.hand_force = 0;
      s.target = s.tool_pos;
      break;
  }
}

double BoxModel::resisted(double v, double f, double resist, double m, double dt_s) {
  const double free = v + f * dt_s / m;
  const double dv_max = resist * dt_s / m;
  if (std::fabs(free) <= dv_max) return 0.0;
  return free - std::copysign(dv_max, free);
}

void BoxModel::step(double dt_s, uint64_t now_us, const std::array<int16_t, 2>& drive, std::array<int64_t, 2>& steps) {
  for (size_t a = 0; a < 2; ++a) {
    const AxisParams& p = params_[a];
    AxisState& s = state_[a];
    hand(a, now_us, dt_s);
    const double level = drive[a] / 1000.0;
    const double motor = p.motor ? level * p.full_scale : 0.0;
    const double brake = p.motor ? 0.0 : std::fabs(level) * p.full_scale;
    const double resist = p.friction_coulomb + brake;
    if (engaged_) {
      // Tool and mechanism as one body: the hand on the tool, the actuator and friction on the
      // mechanism.
      const double m = p.mass + p.tool_mass + (mode_[a] == HandMode::kFree ? 0.0 : p.hand_mass);
      const double f = s.hand_force + motor - p.friction_damping * s.vel;
      const double v = resisted(s.vel, f, resist, m, dt_s);
      const double free = s.vel + f * dt_s / m;
      // The brake's share of what resisted the motion (the rest is the mechanism's friction).
      const double resisted_force = (v - free) * m / dt_s;
      s.actuator_force = p.motor ? motor : (resist > 0 ? resisted_force * brake / resist : 0.0);
      s.actuator_work += s.actuator_force * v * dt_s;
      s.vel = v;
      s.tool_vel = v;
      s.pos += v * dt_s;
      s.tool_pos += v * dt_s;
      if (s.tool_pos > p.travel) {  // the hub at the rollers: no further in
        s.pos -= s.tool_pos - p.travel;
        s.tool_pos = p.travel;
        s.vel = s.tool_vel = std::min(s.vel, 0.0);
      }
    } else {
      // The mechanism alone (a motor spins it, friction stops it); the tool in the hand.
      s.vel = resisted(s.vel, motor - p.friction_damping * s.vel, resist, p.mass, dt_s);
      s.actuator_force = p.motor ? motor : (s.vel == 0.0 ? 0.0 : -std::copysign(brake, s.vel));
      s.actuator_work += s.actuator_force * s.vel * dt_s;
      s.pos += s.vel * dt_s;
      s.tool_vel = std::clamp(s.tool_vel + s.hand_force * dt_s / p.tool_mass, -kHandSpeedLimit[a], kHandSpeedLimit[a]);
      s.tool_pos += s.tool_vel * dt_s;
    }
    const auto count = static_cast<int64_t>(std::floor(s.pos * p.counts_per_unit));
    steps[a] = count - s.count;
    s.count = count;
  }
  // The tool leaves the rollers and the collet when withdrawn past its start, and is taken up
  // again when pushed back in (the bodies' momentum shared).
  AxisState& in = state_[0];
  if (engaged_ && in.tool_pos < 0.0) {
    engaged_ = false;
  } else if (!engaged_ && in.tool_pos >= 0.0 && in.tool_vel > 0.0) {
    engaged_ = true;
    for (size_t a = 0; a < 2; ++a) {
      AxisState& s = state_[a];
      const AxisParams& p = params_[a];
      const double v = (p.mass * s.vel + p.tool_mass * s.tool_vel) / (p.mass + p.tool_mass);
      s.vel = s.tool_vel = v;
    }
  }
}

}  // namespace cathbox::emu

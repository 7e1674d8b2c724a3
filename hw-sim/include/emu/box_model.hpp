#pragma once
// The physical box for one step of simulated time: the tool held by the trainee's hand, passing
// between the insertion rollers (linear axis, m) and through the rotation collet (angular
// axis, rad), each with an encoder and an actuator. A magnetic-particle brake opposes the
// motion with a force up to drive x full scale (and holds the tool when that suffices); a DC
// motor pushes with drive x full scale. The hand follows its script through a spring-damper
// grip, so it feels (and yields to) the actuator. Semi-implicit Euler, fixed step.
#include <array>
#include <cstdint>

#include "emu/hand_script.hpp"

namespace cathbox::emu {

struct AxisParams {
  double mass = 0.05;            // kg (insertion: tool + rollers) or kg*m^2 (rotation)
  double hand_stiffness = 400;   // N/m (N*m/rad): the grip in velocity mode
  double hand_damping = 8;       // N*s/m
  double friction_damping = 2.0; // N*s/m: rollers and bearings
  double full_scale = 5.0;       // N (N*m) at drive 1000
  double full_scale_current_mA = 1000;
  double counts_per_unit = 0;    // encoder counts per m (per rad)
  bool motor = false;            // false: brake (can only resist)
};

struct AxisState {
  double pos = 0;        // m or rad
  double vel = 0;        // m/s or rad/s
  double target = 0;     // where the hand is (velocity mode)
  double hand_force = 0; // last hand force (N, N*m)
  double actuator_force = 0;
  int64_t count = 0;     // true encoder position, counts
};

class BoxModel {
 public:
  BoxModel();
  [[nodiscard]] AxisParams& params(int axis) { return params_[static_cast<size_t>(axis)]; }
  [[nodiscard]] const AxisState& state(int axis) const { return state_[static_cast<size_t>(axis)]; }
  void set_script(int axis, HandScript script, uint64_t start_us);
  // Advances dt_s with the actuators at `drive` (per mille). Returns the encoder steps taken
  // on each axis (each +-1 step is one quadrature edge), written to steps[axis].
  void step(double dt_s, uint64_t now_us, const std::array<int16_t, 2>& drive, std::array<int64_t, 2>& steps);
  // Measured actuator current (mA) for a drive: proportional, signed like the drive.
  [[nodiscard]] int16_t current_mA(int axis, int16_t drive) const;

 private:
  std::array<AxisParams, 2> params_;
  std::array<AxisState, 2> state_;
  std::array<HandScript, 2> script_;
  std::array<uint64_t, 2> script_start_us_{};
};

}  // namespace cathbox::emu

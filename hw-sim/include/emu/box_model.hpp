#pragma once
// The physical box for one step of simulated time: the tool held by the trainee's hand, passing
// between the insertion rollers (linear axis, m) and through the rotation collet (angular
// axis, rad), each with an encoder and an actuator. Two bodies per axis: the mechanism (rollers
// or collet, with the encoder and the actuator's rotor) and the tool in the hand. While the tool
// is between the rollers they move as one, against the mechanism's friction (viscous and
// Coulomb, static = kinetic) and the actuator: a magnetic-particle brake opposes the motion with
// up to drive x full scale and holds the tool when that suffices; a DC motor pushes with
// drive x full scale. Withdrawn past its start (inserted length < 0) the tool leaves the rollers
// and the collet: the encoders then read only the mechanism (a motor spins it, friction stops
// it), the hand moves the tool freely, and pushing it back in picks the mechanism up again.
// Inserted as far as its length, the tool's hub stops at the rollers. The hand follows its
// script through a spring-damper grip, so it feels (and yields to) the box. Semi-implicit Euler,
// fixed step.
#include <array>
#include <cstdint>
#include <limits>

#include "emu/hand_script.hpp"

namespace cathbox::emu {

struct AxisParams {
  double mass = 0.04;             // kg (kg*m^2): rollers (collet), encoder and actuator rotor, at the tool
  double tool_mass = 0.01;        // kg (kg*m^2): the tool and what the hand holds it by
  double hand_stiffness = 400;    // N/m (N*m/rad): the grip in velocity mode
  double hand_damping = 8;        // N*s/m
  double hand_mass = 0;           // kg: the fingers on the tool while they hold it (hand_model.hpp)
  bool hand_impedance_in_force_mode = false;  // pushing with a force: through the grip (true) or a pure force
  double friction_damping = 2.0;  // N*s/m: rollers and bearings, viscous part
  double friction_coulomb = 0.3;  // N (N*m): rollers, bearings and actuator drag, Coulomb part (hw-sim/README.md)
  double full_scale = 5.0;        // N (N*m) at drive 1000
  double full_scale_current_mA = 1000;
  double counts_per_unit = 0;     // encoder counts per m (per rad)
  double travel = std::numeric_limits<double>::infinity();  // m: the tool's length (insertion only)
  bool motor = false;             // false: brake (can only resist)
};

struct AxisState {
  double pos = 0;         // the mechanism: m (rad) at the roller surface (collet): what the encoder reads
  double vel = 0;         // m/s or rad/s
  double tool_pos = 0;    // the tool: inserted length past its start (m), or its angle (rad)
  double tool_vel = 0;
  double target = 0;      // where the hand is (velocity mode; force mode with hand impedance)
  double hand_force = 0;  // last hand force on the tool (N, N*m)
  double actuator_force = 0;
  // Work the actuator has done on the mechanism since the start (J, J): the energy the box put
  // into the tool and the hand. Never above zero for a passive box (closed-loop tests).
  double actuator_work = 0;
  int64_t count = 0;      // true encoder position, counts
};

class BoxModel {
 public:
  // A tool 1.5 m long (a guidewire's working length), not yet inserted: at its start.
  static constexpr double kToolLength = 1.5;
  // The fastest a hand moves a tool (m/s, rad/s), e.g. pulling a tool that left the box.
  static constexpr double kHandSpeedLimit[2] = {1.0, 30.0};

  BoxModel();
  [[nodiscard]] AxisParams& params(int axis) { return params_[static_cast<size_t>(axis)]; }
  [[nodiscard]] const AxisState& state(int axis) const { return state_[static_cast<size_t>(axis)]; }
  // True while the tool is between the rollers and in the collet.
  [[nodiscard]] bool engaged() const { return engaged_; }
  void set_script(int axis, HandScript script, uint64_t start_us);
  // Advances dt_s with the actuators at `drive` (per mille). Returns the encoder steps taken
  // on each axis (each +-1 step is one quadrature edge), written to steps[axis].
  void step(double dt_s, uint64_t now_us, const std::array<int16_t, 2>& drive, std::array<int64_t, 2>& steps);
  // Measured actuator current (mA) for a drive: proportional, signed like the drive.
  [[nodiscard]] int16_t current_mA(int axis, int16_t drive) const;

 private:
  void hand(size_t axis, uint64_t now_us, double dt_s);
  // One body of mass m under force f (besides the resisting ones) with up to `resist` N of
  // friction and brake against its motion: the new velocity (stops and holds when the
  // resistance suffices).
  static double resisted(double v, double f, double resist, double m, double dt_s);

  std::array<AxisParams, 2> params_;
  std::array<AxisState, 2> state_;
  std::array<HandScript, 2> script_;
  std::array<uint64_t, 2> script_start_us_{};
  std::array<HandMode, 2> mode_{HandMode::kFree, HandMode::kFree};  // the hand's last segment mode
  bool engaged_ = true;
};

}  // namespace cathbox::emu

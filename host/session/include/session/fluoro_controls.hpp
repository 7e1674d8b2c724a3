#pragma once
// The fluoroscopy controls (kinds 32..37 of ControlKind): makers for the front ends (keyboard,
// foot pedal, action script, HUD) and the decoding the fluoroscopy unit applies. Payloads are
// little-endian (f64: the IEEE-754 binary64 bits as a u64), documented in host/session/README.md.
#include <cstdint>
#include <optional>

#include "flow/c_arm.hpp"
#include "session/control.hpp"
#include "scenario/action_script.hpp"

namespace cathbox::session::fluoro_control {

[[nodiscard]] Control pedal(bool pressed);
// The contrast's iodine concentration: 300 mgI/mL (iohexol 300) unless said; the payload
// carries it only when it differs (16 bytes, else 24), so records without it read the same.
inline constexpr double kDefaultContrast_mgI_ml = 300.0;
[[nodiscard]] Control inject(double volume_ml, double rate_ml_s, double concentration_mgI_ml = kDefaultContrast_mgI_ml);
[[nodiscard]] Control carm_angles(double lao_deg, double cranial_deg);
[[nodiscard]] Control carm_geometry(double sid_mm, double table_height_mm, double fov_mm, double collimation);
// 7.5, 15 or 30 pulses per second (stored as pulses per 10 s).
[[nodiscard]] Control pulse_rate(double per_s);
[[nodiscard]] Control roadmap(bool capture);

// An action script's imaging verb as its control (fluoro, inject, carm, roadmap); none for
// the other verbs.
[[nodiscard]] std::optional<Control> from_action(const tool::Action& action);

// Decoding; nullopt when the payload has the wrong size.
struct InjectPayload {
  double volume_ml = 0.0;
  double rate_ml_s = 0.0;
  double concentration_mgI_ml = kDefaultContrast_mgI_ml;
};
struct AnglesPayload {
  double lao_deg = 0.0;
  double cranial_deg = 0.0;
};
struct GeometryPayload {
  double sid_mm = 0.0;
  double table_height_mm = 0.0;
  double fov_mm = 0.0;
  double collimation = 0.0;
};
[[nodiscard]] std::optional<bool> read_flag(const Control& c);  // pedal, roadmap
[[nodiscard]] std::optional<InjectPayload> read_inject(const Control& c);
[[nodiscard]] std::optional<AnglesPayload> read_angles(const Control& c);
[[nodiscard]] std::optional<GeometryPayload> read_geometry(const Control& c);
[[nodiscard]] std::optional<double> read_pulse_rate(const Control& c);

}  // namespace cathbox::session::fluoro_control

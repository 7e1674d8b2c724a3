#pragma once
// The command the trainee page sends its box: the held tool's local force law (stiffness and
// damping included) shaped by session::PassiveLaw and encoded by device::force_law_command, the
// native BoxHand's own path (host/session/src/box_hand.cpp), so the same law and readback give the
// same bytes. Configured from the box's feature reports as BoxHand::init does (the full scale is
// the smaller of the limits' and the calibration's, the slew limit the limits'); the page's box
// frame is given as the offset from the session's insertion/rotation to the box's (mm, rad from
// the box's count zero), which the page's servo keeps.
#include <cstdint>

#include "protocol/cbx_command_report.h"
#include "session/passive_law.hpp"
#include "tool/force_law.hpp"

namespace cathbox::wasm {

struct BoxLawConfig {
  double full_scale_mN = 5000.0;
  double slew_mN_per_ms = 100.0;
  double command_period_ms = 1.0;  // how often the page sends a command
  std::uint8_t mode = CBX_MODE_BRAKE;
};

struct BoxReading {
  double force_mN = 0.0;    // the box's rendered output (state report), + pushes in
  double speed_mm_s = 0.0;  // its insertion speed, calibrated
};

class BrowserBoxLaw {
 public:
  void configure(const BoxLawConfig& config);
  // The command for `session_law` with the box's frame at session + (box_offset_mm, box_offset_rad).
  [[nodiscard]] cbx_command_report command(const tool::ForceLaw& session_law, double box_offset_mm,
                                           double box_offset_rad, const BoxReading& reading);
  // Outputs were off: the next law starts from zero force.
  void reset() { passive_.reset(); }

 private:
  std::uint8_t mode_ = CBX_MODE_BRAKE;
  session::PassiveLaw passive_;
};

}  // namespace cathbox::wasm

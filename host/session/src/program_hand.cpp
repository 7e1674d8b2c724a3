#include "session/program_hand.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::session {

ProgramHand::ProgramHand(double dt_s, std::string who) : dt_s_(dt_s), description_(std::move(who)) {}

void ProgramHand::set_speed(std::size_t tool, ToolSpeed speed) {
  if (tool < kMaxTools) speeds_[tool] = speed;
}

void ProgramHand::restart(std::size_t tool, const ToolCommand& at) {
  if (tool >= kMaxTools) return;
  insertion_um_[tool] = static_cast<double>(at.insertion_um);
  rotation_urad_[tool] = static_cast<double>(at.rotation_urad);
}

void ProgramHand::read(std::int64_t, TickInput& in) {
  if (!started_) {  // carry on from where the session has the tools
    for (std::size_t t = 0; t < in.tool_count; ++t) restart(t, in.tools[t]);
    started_ = true;
  }
  for (std::size_t t = 0; t < in.tool_count; ++t) {
    const double max_um = static_cast<double>(in.max_insertion_um[t]);
    insertion_um_[t] = std::clamp(insertion_um_[t] + speeds_[t].insertion_mm_s * 1e3 * dt_s_, 0.0, max_um);
    rotation_urad_[t] += speeds_[t].rotation_rad_s * 1e6 * dt_s_;
    in.tools[t] = {std::llround(insertion_um_[t]), std::llround(rotation_urad_[t])};
  }
}

}  // namespace cathbox::session

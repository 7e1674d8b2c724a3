#pragma once
// A program's hand: every tool moves at the speeds a program sets between ticks (the Python
// module's environments: an agent's actions in mm/s and rad/s). Each tick integrates the speeds
// over the period into whole µm / µrad, as a box would report them, keeping the fractions, so
// a speed of 0.5 µm per tick moves 1 µm every other tick. The insertion stays within
// [0, max] of its tool (a push past either end is cut: no dead zone on the way back).
// Deterministic: the positions depend only on the speeds and when they were set; the record
// holds the integers, so a replay does not need this hand.
#include <array>
#include <cstddef>
#include <string>

#include "session/hand.hpp"

namespace cathbox::session {

struct ToolSpeed {
  double insertion_mm_s = 0.0;
  double rotation_rad_s = 0.0;
};

class ProgramHand final : public Hand {
 public:
  // dt_s: the session's period; `who` names the program in the record's hand description.
  ProgramHand(double dt_s, std::string who);

  [[nodiscard]] HandKind kind() const override { return HandKind::kProgram; }
  [[nodiscard]] std::string describe() const override { return description_; }
  void restart(std::size_t tool, const ToolCommand& at) override;
  void read(std::int64_t tick, TickInput& input) override;

  // Between ticks (the thread that steps the session): the speed of `tool` from the next tick.
  // Speeds must be finite (the caller checks).
  void set_speed(std::size_t tool, ToolSpeed speed);
  [[nodiscard]] ToolSpeed speed(std::size_t tool) const { return speeds_[tool]; }

 private:
  double dt_s_;
  std::string description_;
  bool started_ = false;
  std::array<ToolSpeed, kMaxTools> speeds_{};
  std::array<double, kMaxTools> insertion_um_{};  // with fractions
  std::array<double, kMaxTools> rotation_urad_{};
};

}  // namespace cathbox::session

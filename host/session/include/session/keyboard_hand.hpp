#pragma once
// The keyboard and mouse in place of the box: the held tool moves at the speeds the render
// thread sets (KeyboardInput); Tab posts a select control to the session.
#include <string>

#include "session/hand.hpp"
#include "session/hand_mapping.hpp"
#include "session/keyboard_input.hpp"

namespace cathbox::session {

class KeyboardHand final : public Hand {
 public:
  // `input` is shared with the render thread and outlives the hand; dt_s is the tick period.
  KeyboardHand(KeyboardInput& input, double dt_s, std::string why = "keyboard");

  [[nodiscard]] HandKind kind() const override { return HandKind::kKeyboard; }
  [[nodiscard]] std::string describe() const override { return description_; }
  void hold(std::size_t tool, const ToolCommand& at) override { mapping_.hold(tool, at); }
  void restart(std::size_t tool, const ToolCommand& at) override {
    if (tool == mapping_.held()) mapping_.hold(tool, at);
  }
  void read(std::int64_t tick, TickInput& input) override;

 private:
  KeyboardInput& input_;
  double dt_s_;
  std::string description_;
  HandMapping mapping_;
};

}  // namespace cathbox::session

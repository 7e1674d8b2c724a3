#include "session/keyboard_hand.hpp"

namespace cathbox::session {

KeyboardHand::KeyboardHand(KeyboardInput& input, double dt_s, std::string why)
    : input_(input), dt_s_(dt_s), description_(std::move(why)) {}

void KeyboardHand::read(std::int64_t, TickInput& in) {
  const KeyboardInput::Motion m = input_.take(dt_s_);
  mapping_.nudge(m.insertion_um, m.rotation_urad, in.max_insertion_um[in.held]);
  in.tools[in.held] = mapping_.command({});
}

}  // namespace cathbox::session

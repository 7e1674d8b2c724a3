#pragma once
// The held tool's tip as the hand feels it (single precision, the session's frame): shared by the
// feedback before the first tick (session_setup.cpp) and every tick's (session.cpp).
#include <glm/glm.hpp>

#include "session/hand.hpp"
#include "tool/snapshot.hpp"

namespace cathbox::session {

inline void set_tip_feedback(HandFeedback& fb, const tool::ToolSnapshot& held) {
  fb.tip_mm = glm::vec3(held.tip.position_mm);
  fb.tip_direction = glm::vec3(held.tip.direction);
  fb.tip_bend = glm::vec3(held.tip.normal);
}

}  // namespace cathbox::session

#pragma once
// How the trainee's hand holds the tool in the emulated box: the impedance between the hand's
// scripted motion (HandScript) and the tool.
//   kScripted: the grip cathbox-emu has always used, 400 N/m and 8 N*s/m, massless; pushing
//              with a force it is a pure force source (no impedance of its own).
//   kFinger:   a thumb and index finger pinching a wire, as a mass-spring-damper from the
//              fingertip impedance measured by Hajian & Howe 1997 (J. Biomech. Eng. 119:109,
//              "Identification of the mechanical impedance at the human finger tip"): effective
//              mass of a few grams, damping of a few N*s/m, stiffness a few hundred N/m that rises
//              with the force pressed (values in hw-sim/README.md). Pushing with a force, the
//              arm holds still and the finger presses through that impedance; letting go, the
//              finger's mass leaves the tool.
#include <optional>
#include <string_view>

#include "emu/box_model.hpp"

namespace cathbox::emu {

enum class HandModel { kScripted, kFinger };

// "scripted" or "finger"; none for anything else.
[[nodiscard]] std::optional<HandModel> parse_hand_model(std::string_view name);
// Sets the insertion axis's grip (AxisParams hand_*) for the model.
void apply_hand_model(HandModel model, AxisParams& insertion);

}  // namespace cathbox::emu

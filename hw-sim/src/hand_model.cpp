#include "emu/hand_model.hpp"

namespace cathbox::emu {

std::optional<HandModel> parse_hand_model(std::string_view name) {
  if (name == "scripted") return HandModel::kScripted;
  if (name == "finger") return HandModel::kFinger;
  return std::nullopt;
}

void apply_hand_model(HandModel model, AxisParams& p) {
  const AxisParams defaults;
  switch (model) {
    case HandModel::kScripted:
      p.hand_mass = defaults.hand_mass;
      p.hand_stiffness = defaults.hand_stiffness;
      p.hand_damping = defaults.hand_damping;
      p.hand_impedance_in_force_mode = false;
      break;
    case HandModel::kFinger:
      // Hajian & Howe 1997, index fingertip, within their measured ranges at the 1-3 N a
      // trainee pushes a wire with: 6 g, 3 N*s/m, 300 N/m.
      p.hand_mass = 0.006;
      p.hand_stiffness = 300.0;
      p.hand_damping = 3.0;
      p.hand_impedance_in_force_mode = true;
      break;
  }
}

}  // namespace cathbox::emu

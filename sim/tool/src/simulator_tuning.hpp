// The simulator's coupling constants that its step and its sheath path share.
#pragma once

namespace cathbox::tool::tuning {
inline constexpr double kCouplingRelaxation = 0.5;  // loads from inner tools: new = r new + (1 - r) old
// The push of a carried wire on its balloon catheter's tip, lagged a tick: new = r new + (1 - r)
// old. The angioplasty run's guidewire is unconverged on 0.04 % of its ticks at 0.1, 0.16 % at 0.5.
inline constexpr double kTipPushRelaxation = 0.1;
// Most sub-increments a lone tool's unconverged tick is solved again in (RodSettings::substeps_max).
inline constexpr int kLoneToolSubsteps = 4;
inline constexpr double kMinSheathEdge = 0.5;  // shortest sheath-path edge, of the holder's node spacing
}  // namespace cathbox::tool::tuning

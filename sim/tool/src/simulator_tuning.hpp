// The simulator's coupling constants that its step and its sheath path share.
#pragma once

namespace cathbox::tool::tuning {
inline constexpr double kCouplingRelaxation = 0.5;  // loads from inner tools: new = r new + (1 - r) old
// A coil's axial force pushing on its catheters' turns (SheathFriction::set_bend_reaction; the
// reactions then sum to its free-body balance). Off, the held microcatheter felt the coil's lumen
// friction alone, which dragged it forwards (the dense case's tip climbed into its 4 mm sac and the
// frame's end herniated; the bundled run detached both coils under ~200 mN of tension). On, each
// coil detaches in neutral (9-22 mN), the dense case's three coils pack 26.59 % without
// herniation, and the bundled run's microcatheter kicks back 3.30 mm from the 4 mm its tip climbs
// as each pusher is drawn back, staying in the sac (docs/sim-tool/coiling.md, "The coil's push
// on its catheter's turns").
inline constexpr bool kCoilBendReaction = true;
// The push of a carried wire on its steered catheter's tip, lagged a tick: new = r new + (1 - r)
// old. The angioplasty run's guidewire is unconverged on 0.04 % of its ticks at 0.1, 0.16 % at 0.5.
inline constexpr double kTipPushRelaxation = 0.1;
// The most that push changes in a step on a balloon catheter, or on a catheter with a guidewire
// hinged at its tip (Simulator::push_bounded; decay and new push together): the
// relaxation times the box's slew (100 mN a tick), so an inner tool's clamp that changes by up to
// the slew moves it at the full relaxed rate and a wall touch's 700-850 mN at the slew's
// (Simulator::limit_tip_push).
inline constexpr double kTipPushSlew_mN = kTipPushRelaxation * 100.0;
// While a tool leaving the catheter is drawn back into it, that bound adapts to the push's own
// reversals as Rprop's step does (Riedmiller & Braun, ICNN 1993): a change against the last one
// halves the share of the slew the push may change by, one along it (or none) regrows it by 1.2,
// between the floor and the whole slew. The M1 Solumbra run's microcatheter drawn back at 20 mm/s
// into its aspiration catheter: that catheter's push swung +-10 mN every tick, its tip +-0.1 mm,
// and the microcatheter's last 1-2 mm tapped the wall every other tick (43 held ticks over the
// box's slew, 810.9 mN); halved at reversals, 4 ticks and 120.6 mN.
inline constexpr double kPushSlewDown = 0.5;
inline constexpr double kPushSlewUp = 1.2;
inline constexpr double kPushSlewFloor = 1.0 / 16.0;
// Most sub-increments a lone tool's unconverged tick is solved again in (RodSettings::substeps_max).
inline constexpr int kLoneToolSubsteps = 4;
// And a catheter directly in a balloon guide (the aspiration stacks' aspiration catheter): its pass,
// withdrawn at 10 mm/s with the clot, its tip snapping back down the terminal ICA, left 162
// ticks unconverged after 4 parts in the ADAPT M1 run (0.50 %), ~102 after 8 (0.32 %;
// convergence.md, "An aspiration stack sub-stepped"). And every guidewire: the dense coiling
// run's microwire, hinged at its microcatheter's tip while drawn back, has a short free part
// whose tip and base touch the sac wall and whose Newton steps swing between the two contacts'
// active sets (0.01-0.1 mm, never under convergence_mm): 36 ticks unconverged after 4 parts
// (0.52 %), 4 after 8 (0.06 %; convergence.md, "A wire drawn back bends from its catheter's tip").
// Every sub-stepped tool at 8 moved the dense run's third coil into the parent artery.
inline constexpr int kFineSubsteps = 8;
// A released coil's warm start (RodSettings::warm_start): a coil pushed at a steady rate starts
// each step from its whole last motion (1), but a released one only relaxes, and with 1 the
// extrapolated motion is carried into the next step undiminished (its friction anchors and
// contacts gathered at the extrapolated start keep it): the packing bench's held pile crept
// 3-17 um a tick without end. At 0.5 the carried motion halves each step and the pile settles
// (0.02 um a tick on average at 3-4 s, 1.04 Newton iterations a step; 0 settles alike with 1.40):
// docs/journal/sim-tool-step-time.md, "What keeps the packing bench's pile moving".
inline constexpr double kReleasedCoilWarmStart = 0.5;
// How long a detachment zone takes to part once detach starts it (Simulator::advance_partings):
// its joint's bending and twisting stiffness fall as (1 - t / T)^4 to nothing at T, the coil then
// released. The moment the joint held leaves the hand over T, at first 4 / T of it a second
// (docs/sim-tool/coiling.md, "Detachment: the zone parts").
inline constexpr double kDetachParting_s = 0.1;
// A released coil is solved on every kReleasedCoilTicks-th tick only, over that many ticks' time,
// the coils taking turns (coil i on the steps where step + i is a multiple of it): a released pile
// is overdamped and near rest (BM_StepCoilPacking's two released coils move 1.9 um a tick on
// average against the rod-contact field's 50 um margin), and its implicit step is stable at any
// length, its fixed point the static equilibrium. Solving the pile on every second tick halves its
// cost in a tick: the packing bench's median step 837 -> 596 us, and the dense case at rig speed
// drops 395 ticks instead of 3,398 (docs/sim-tool/coiling.md, "Released coils on their turns").
// At a quarter rate the dense case's framing coil herniated once (0.17 mm past the neck).
inline constexpr int kReleasedCoilTicks = 2;
}  // namespace cathbox::tool::tuning

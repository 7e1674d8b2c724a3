#pragma once
// Shapes the held tool's force law (box frame, sim/tool/force_law.hpp) into one the box can
// render without putting energy into the hand, before BoxHand sends it (docs/passive_rendering.md):
//   1. Full scale: the force at the law's position stays within the box's max_force_mN.
//   2. Slew: from one command to the next, the law's force changes by at most the box's
//      force_slew_mN_per_ms per tick, and the command's output range (out_min, out_max) is the
//      box's readback +- that step, so what the box renders (the law's spring followed by the
//      hand, its damper when the hand stops) moves at most a step a tick: the simulation, not
//      only the firmware's clamp, respects the box's slew limit. The step is taken from the last
//      law's force, not from its spring carried to the new position: the spring is the
//      simulation's linearisation, and a stick anchor's (a valve or lumen, 2e4 mN/mm) slips
//      within microns or moves with the catheter round the tool; slewed from it, the sent force
//      climbed k dx - step a tick to the full scale while the tool's own force was 0.
//   3. Sampled stiffness (Colgate & Schenkel 1997, "Passivity of a class of sampled-data
//      systems"): a spring K rendered with sample period T is passive when the damping it
//      meets exceeds K T / 2. The simulation's stiffness reaches the hand through the 1 ms
//      command as well as the 10 kHz law, so damping is added to b >= K T / 2 with T the
//      command period, minus the box's own friction damping. K is the law's: the simulation
//      leaves out the stick anchors of a catheter that moved (Simulator::force_law), which are
//      no spring about a point fixed in the box's frame.
//   5. Held resistance (a virtual coupling's damper, Colgate, Stanley & Brown 1995): when the simulation's force drops
//      faster than the grip can follow (a wire that buckles), the resistance it had is not
//      let go at once as a spring would release the grip, but kept as a damper that lets the
//      tool advance (while it goes in) no faster than follow_mm_s beyond the hand, capped at that resistance and
//      fading over hold_ms. A damper only takes energy out.
//   4. Passivity observer / controller (Hannaford & Ryu 2002, "Time-domain passivity control
//      of haptic interfaces"): the energy the box has delivered, summed from its readback
//      (rendered force x measured speed); while it is above zero, damping alpha = E / (v^2 T)
//      is added to the next law to take it out again.
#include <algorithm>
#include <cstdint>

#include "tool/force_law.hpp"

namespace cathbox::session {

struct PassiveLawLimits {
  double full_scale_mN = 5000.0;          // the box's max_force_mN
  double slew_mN_per_ms = 100.0;          // the box's force_slew_mN_per_ms
  double tick_ms = 1.0;                   // the command period
  double box_damping_mN_s_per_mm = 0.0;   // the mechanism's own viscous friction (0: unknown)
  double max_damping_mN_s_per_mm = 200.0; // the passivity controller's ceiling
  double follow_mm_s = 10.0;              // 5: the speed a dropped resistance lets the tool take
  double hold_ms = 500.0;                 // 5: how long a dropped resistance fades
};

// What the box reported at this tick (protocol state report, calibrated).
struct BoxReadback {
  double force_mN = 0.0;        // rendered output, + pushes into the patient
  double speed_mm_s = 0.0;      // insertion speed, + into the patient
};

// The law to send and the box output's range (protocol out_min / out_max, + into the patient).
struct ShapedLaw {
  tool::ForceLaw law;
  double out_min_mN = 0.0;
  double out_max_mN = 0.0;
  // What the box outputs (+ into the patient) for this law with the tool at `insertion_mm` (box
  // frame) moving at `speed_mm_s`: the protocol's `offset - k (pos - pos0) - b vel`, within
  // [out_min, out_max]. Before the firmware's own clamp and slew (firmware/core cbx_render.c).
  [[nodiscard]] double output_mN(double insertion_mm, double speed_mm_s) const {
    return std::clamp(-law.force_mN(insertion_mm, speed_mm_s), out_min_mN, out_max_mN);
  }
};

class PassiveLaw {
 public:
  PassiveLaw() = default;
  explicit PassiveLaw(PassiveLawLimits limits) : limits_(limits) {}

  // The law to send for `law` (box frame; its force resists insertion) given what the box
  // rendered since the last command.
  [[nodiscard]] ShapedLaw shape(const tool::ForceLaw& law, const BoxReadback& readback);
  // The last law shaped (box frame).
  [[nodiscard]] const tool::ForceLaw& last() const { return last_; }
  // Forgets the previous command (outputs were off; the next law starts from zero force).
  void reset();
  // The observer's energy (mJ): what the box has delivered to the hand, net, since reset.
  [[nodiscard]] double observed_energy_mJ() const { return energy_mJ_; }
  [[nodiscard]] const PassiveLawLimits& limits() const { return limits_; }

 private:
  PassiveLawLimits limits_;
  tool::ForceLaw last_;
  bool have_last_ = false;
  double energy_mJ_ = 0.0;
  double held_mN_ = 0.0;  // 5: the resistance held since the simulation's force dropped
};

}  // namespace cathbox::session

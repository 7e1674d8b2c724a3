#include "session/passive_law.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::session {

void PassiveLaw::reset() {
  have_last_ = false;
  energy_mJ_ = 0.0;
  held_mN_ = 0.0;
}

ShapedLaw PassiveLaw::shape(const tool::ForceLaw& law, const BoxReadback& readback) {
  tool::ForceLaw out = law;
  const double tick_s = limits_.tick_ms * 1e-3;
  // 4. Passivity observer: the box's output (+ into the patient) times the tool's speed is the
  // power it puts into the tool and the hand; mN * mm/s * s = uJ.
  energy_mJ_ += readback.force_mN * readback.speed_mm_s * tick_s * 1e-3;
  double damping = std::max(0.0, out.damping_mN_s_per_mm);
  // 3. Sampled stiffness: b >= K T / 2 (mN/mm * s = mN s/mm).
  const double stiffness = std::max(0.0, out.stiffness_mN_per_mm);
  damping = std::max(damping, stiffness * tick_s / 2.0 - limits_.box_damping_mN_s_per_mm);
  const double v = readback.speed_mm_s;
  if (energy_mJ_ > 0.0 && std::fabs(v) > 1e-3) {
    // Controller: dissipate the surplus over the next tick (mJ = mN mm * 1e-3).
    const double alpha = std::min(energy_mJ_ * 1e3 / (v * v * tick_s), limits_.max_damping_mN_s_per_mm);
    damping += alpha;
    energy_mJ_ -= alpha * v * v * tick_s * 1e-3;
  }
  out.damping_mN_s_per_mm = std::min(damping, std::max(limits_.max_damping_mN_s_per_mm, out.damping_mN_s_per_mm));
  out.stiffness_mN_per_mm = stiffness;
  // 2. Slew: the force at the new position, against the last law's force (the simulation's step
  // says where its spring went; carried on, a slipped stick spring ratchets: passive_law.hpp).
  const double step = limits_.slew_mN_per_ms * limits_.tick_ms;
  const double before = have_last_ ? last_.force0_mN : 0.0;
  out.force0_mN = std::clamp(out.force0_mN, before - step, before + step);
  // 1. Full scale.
  out.force0_mN = std::clamp(out.force0_mN, -limits_.full_scale_mN, limits_.full_scale_mN);
  // 5. Held resistance: a damper of up to what the force dropped from, fading over hold_ms.
  const double fade = std::exp(-limits_.tick_ms / std::max(limits_.hold_ms, 1e-9));
  held_mN_ = std::max(out.force0_mN, held_mN_ * fade + out.force0_mN * (1.0 - fade));
  if (have_last_) held_mN_ = std::max(held_mN_, std::min(before, limits_.full_scale_mN) * fade);
  held_mN_ = std::min(held_mN_, limits_.full_scale_mN);
  ShapedLaw shaped;
  shaped.out_min_mN = -limits_.full_scale_mN;
  shaped.out_max_mN = limits_.full_scale_mN;
  const double deficit = held_mN_ - out.force0_mN;
  // Only while the tool goes in: going out (a wire relaxing after the hand let go) the damper
  // would only slow it down.
  if (deficit > 0.0 && limits_.follow_mm_s > 0.0 && readback.speed_mm_s > 0.0) {
    out.damping_mN_s_per_mm += deficit / limits_.follow_mm_s;
    // The resistance never exceeds what was held (pulling back: the damper's own sign).
    shaped.out_min_mN = -held_mN_;
  }
  // 2. Slew of the output: whatever the law's spring and damper give between commands (the hand
  // moving along k, a damper's force vanishing when the hand stops), the box renders within a
  // step of what it rendered last (its readback; 0 after a reset, outputs off), which is the
  // box's own limit.
  shaped.out_min_mN = std::clamp(readback.force_mN - step, shaped.out_min_mN, shaped.out_max_mN);
  shaped.out_max_mN = std::clamp(readback.force_mN + step, shaped.out_min_mN, shaped.out_max_mN);
  last_ = out;
  have_last_ = true;
  shaped.law = out;
  return shaped;
}

}  // namespace cathbox::session

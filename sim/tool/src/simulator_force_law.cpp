// The simulator's force laws: what each tool's box renders between steps, and an unconverged
// tick's, held to the last converged tick's.
#include "tool/simulator.hpp"

namespace cathbox::tool {

// The hand force, torque and law of an unconverged tick (issue 29: "a tick that does not converge
// still gives a force consistent with the last converged state, never a leftover penetration
// times a penalty"): a tool whose solve ends this tick unconverged (after its sub-steps) keeps
// its last converged tick's force and torque, and the law that tick's stiffness and damping about
// where the hand is now (force_law). Its state goes on from the unconverged solve as before: only
// what the hand feels is held. Without it the ADAPT pass's aspiration catheter, unconverged at
// 61.129 s with a node on the wall at 2,605 mN, moved the hand by +114.3 and -100.0 mN in two
// ticks (convergence.md, "An unconverged tick's hand force held").
void Simulator::hold_unconverged() {
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    const Rod& rod = rods_[t];
    const bool unconverged = rod.first_free_node() < rod.node_total() && !rod.converged();
    held_[t] = unconverged && converged_law_[t].has_value() ? 1 : 0;
    if (held_[t] != 0) {
      hand_force_[t] = converged_law_[t]->force0_mN;
      hand_torque_[t] = converged_law_[t]->torque0_mNmm;
    } else if (!unconverged) {
      converged_law_[t] = force_law(t);
    }
  }
}

ForceLaw Simulator::force_law(std::size_t tool) const {
  ForceLaw law = rods_[tool].force_law();
  if (held_[tool] != 0) {
    ForceLaw held = *converged_law_[tool];
    held.insertion0_mm = insertion_[tool];
    held.rotation0_rad = law.rotation0_rad;
    return held;
  }
  // The inner tool's law is expressed in its own insertion, not its protrusion; every law
  // carries the friction of the lumens and the valve around the tool.
  law.insertion0_mm = insertion_[tool];
  law.force0_mN = hand_force_[tool];
  law.torque0_mNmm = hand_torque_[tool];
  // A stuck anchor (the lumen's, its shafts' compliance: sheath_anchor.hpp; or the valve's stick
  // spring) is stated as a spring only while what it holds the tool to, the catheter round it
  // (the patient for a valve on a tool in the vessel), did not move in the step. The box renders
  // a law's spring about a point fixed in its own frame; an anchor on a catheter that moves is
  // not one (the coiling run's microwire advanced with its microcatheter at 20 mm/s: stated, its
  // 2 x 2e4 mN/mm had PassiveLaw add the K T / 2 damper, 400 mN of drag, while the wire's force
  // was 0). It still reaches the hand
  // through the force, each step, bounded by its slip limit (docs/session/passive-rendering.md).
  const std::size_t o = outer_of_[tool];
  const bool held_in_place = o >= rods_.size() || moved_mm_[o] == 0.0;
  const bool held_in_turn = o >= rods_.size() || turned_rad_[o] == 0.0;
  const double radius = rods_[tool].radius_at_mm(0.0);
  if (o < rods_.size()) {
    const SheathFriction::Result& r = sheath_result_[tool];
    const double k_sheath = r.anchor_mN_per_mm;  // the step's, sheath_anchor.hpp
    if (held_in_place && r.sticking && (r.force_limit_fwd_mN > 0.0 || r.force_limit_back_mN < 0.0)) {
      law.stiffness_mN_per_mm += k_sheath;
    }
    if (held_in_turn && r.twist_sticking && r.torque_limit_mNmm > 0.0) {
      law.torsion_stiffness_mNmm_per_rad += k_sheath * radius * radius;
    }
  }
  const ValveFriction::Result& v = valve_result_[tool];
  const bool in_valve = insertion_[tool] > 0.0;
  const double k_valve = settings_.stick_stiffness_mN_per_mm();
  if (held_in_place && v.sticking && in_valve) law.stiffness_mN_per_mm += k_valve;
  if (held_in_turn && v.twist_sticking && in_valve) law.torsion_stiffness_mNmm_per_rad += k_valve * radius * radius;
  return law;
}

}  // namespace cathbox::tool

#pragma once
// Numerical settings of the rod solver. The defaults suit the 1 kHz haptic loop; validation
// tests raise the iteration count to reach static equilibrium tightly.
#include <limits>

#include "tool/arterial_wall.hpp"

namespace cathbox::tool {

// The shortest the clamp edge bends over, in its rest length, when the clamp's hinge is at the
// entry point (RodSettings::clamp_hinge_at_entry): its bending stiffness grows as 1 / length, so
// the hinge stays within this much of an edge behind the entry.
inline constexpr double kClampEdgeFloor = 0.05;

struct RodSettings {
  int newton_iterations = 8;               // most Gauss-Newton iterations on positions per step
  // A tick whose solve ends unconverged is solved again from its start in 2, then 4 ... (up to
  // this many) sub-increments of the imposed motion, each of dt / parts (rod_substep.cpp,
  // docs/sim-tool/convergence.md). 1: never (the default; the Simulator gives lone tools 4).
  int substeps_max = 1;
  int twist_iterations = 2;                // Newton iterations on the twist angles per step
  double contact_stiffness_mN_per_mm = 2.0e5;  // wall penalty per node
  // Wall friction's stick spring at a node: the tissue's tangential contact stiffness under the
  // node's patch (arterial_wall.hpp, Mindlin), per mm of the node's radius. The cervical wall's
  // (1,369 mN/mm^2: 246 mN/mm under a 0.014" wire) on a rigid wall too, whose normal stiffness is
  // a numerical penalty; a case's `wall` line sets its territory's. 0: the ratio below (coils).
  double wall_shear_mN_per_mm2 = patch_shear_stiffness_mN_per_mm2(kCervicalWall);
  // The stick springs that are not the wall's nor the lumen's (rod-rod contact, a balloon's grip,
  // the valve anchors): this fraction of contact_stiffness_mN_per_mm.
  double stick_stiffness_ratio = 0.1;
  // Those stick springs' stiffness.
  [[nodiscard]] double stick_stiffness_mN_per_mm() const { return contact_stiffness_mN_per_mm * stick_stiffness_ratio; }
  double contact_margin_mm = 0.15;         // nodes this close to the wall get a contact plane
  double query_range_mm = 1.5;             // wall search distance; beyond it a node is free
  double requery_move_mm = 0.02;           // re-probe after the first iteration if a node moved more
  // The wall against edges where it bulges between two nodes (a carina's apex): rod_edge_wall.cpp.
  // Off by default: on, a stent retriever in a faceted mesh tube needs 6.0 Newton iterations a
  // step (1.6 off) and coiling's microwire share rises (sim/tool/README.md, "Limits").
  bool edge_wall_contact = false;
  double max_node_step_mm = 0.2;           // largest position update of one iteration
  // Numerical damping: the solver never damps a node less than this (blood's drag is ~1e-5);
  // the excess is taken back out of the force and torque the hand feels.
  double min_drag_mN_s_per_mm2 = 1.0e-2;
  // Stop iterating when the largest Newton update (the full step, before the line search or
  // the max_node_step_mm cap shortens it) is smaller: a step the line search cut short is no
  // sign of a solution.
  double convergence_mm = 2.0e-3;
  // Nor when the iteration's active-set update let go of a node whose plane still pulled it by
  // more than this: the wall's quadratic, continued below 0 for an active node, then pulls it,
  // and a stiff tool that barely moves converges with that pull in its clamp's force (a pull no
  // contact has). Half the box's force slew a tick: a pull that large reads as a jump at the
  // hand (the ICA-T Solumbra run drew 106-438 mN this way). Infinity: never.
  double release_pull_mN = 50.0;
  bool reuse_hessian = false;              // chord iterations while the active set is unchanged
  // A full step the energy took unshortened is extended to the minimum of the energy's parabola
  // along it (at most extend_max times), when that is lower: the Gauss-Newton Hessian holds a
  // buckled rod's slow modes stiffer than they are (docs/sim-tool/convergence.md).
  double extend_max = 8.0;
  // Halve an update below trust_step_mm nearly undoing the last. Off by default: every update
  // now goes through the line search, which breaks the friction two-cycles this was made for.
  bool damp_reversals = false;
  // Planes of other rods (and of the rod's far parts) the Newton step would cross: open, they are
  // out of the Hessian, so the step went through them and the line search cut it to a few per
  // cent. Their penalty is taken into the step's model and it is solved again, up to this many
  // times an iteration (rod_edge_contact.cpp, predict_edge_contacts). 0: never.
  int contact_predictions = 8;
  double trust_step_mm = 0.01;             // reversal damping applies below this update
  // Warm start: a step whose predecessor converged (and ended with no edge compressed by more
  // than warm_start_strain) and that is not given a buckling seed starts its Newton iterations
  // from the advected positions plus this fraction of each free node's motion in that step (the
  // solve and the wall clamp), instead of from the advected positions alone. The equilibrium
  // sought is the same; a tool still moving is met nearer it. 0 turns it off.
  double warm_start = 0.5;
  // A jammed tool (compressed past this strain: 2.5 N at the default EA) starts cold: its
  // buckled motion extrapolated keeps shaking it. A catheter pushed round the siphon is
  // compressed past buckling_strain on most steps; cold there, the ADAPT session's aspiration
  // catheter went unconverged on 17 % of its ticks and jammed (docs/sim-tool/convergence.md,
  // "The warm start after the seed").
  double warm_start_strain = 5.0e-4;
  // Read the clamp force at the linearised equilibrium of the last Newton step (its whole
  // step) rather than at the final positions. Always so for a rod among other rods; a coil tool
  // sets it for its whole life, since its stiff axial springs read 1 um of residual as newtons
  // (its pusher too, once the coil is released and it leaves the contact field).
  bool linearised_clamp = false;
  // The follow-the-leader predictor slides nodes along circular arcs through their neighbours
  // instead of along the chords between them (coils: a chord slide shortens every edge of a
  // loop, which the stiff axial springs then push back out in the solve).
  bool arc_predictor = false;
  // The clamp's hinge at the entry point: the clamp edge (the last node not past the entry to
  // the first free node) bends from the entry point, not from that node (up to an edge behind
  // the entry), over the part of it past the entry (at least kClampEdgeFloor of it; the edge
  // stretches node to node), so a node crossing the entry changes the free part's compliance by
  // no step. Off: the hinge at the clamp node, half an edge of compliance gained or lost at
  // every crossing. The Simulator sets it for a tool alone in the body, every catheter, every
  // coil (Rod::update_window leaves it out while a coil's joint or pusher is the clamp node) and a
  // wire in a catheter it steers, and off for a wire in an unsteered catheter
  // (Simulator::hinged_at_entry), which bends from the entry only while its hand draws it back
  // (Rod::hinge_while_drawn_back, switched at node crossings; docs/sim-tool/convergence.md, "The
  // clamp's hinge at the entry point", where the other tools' runs with it are measured,
  // "Catheters hinged at the entry", "Wires hinged in the catheters they steer", "Coils hinged
  // at the entry" and "A wire drawn back bends from its catheter's tip").
  bool clamp_hinge_at_entry = true;
  double max_penetration_ratio = 0.05;     // hard limit of wall penetration, in tool radii
  // A compliant wall's layer (wall_penalty.hpp): past this penetration the wall's contact
  // stiffness is wall_stiffening times contact_stiffness_mN_per_mm. Infinity: one stiffness.
  double wall_layer_mm = std::numeric_limits<double>::infinity();
  double wall_stiffening = 10.0;
  // The wall's gap follows its curvature (estimated from successive probes, along two
  // directions): a node pressed on a concave wall is held along it by its force over the radius
  // of curvature. A plane alone lets the node slide along its tangent, out of a lumen whose
  // centre path curves at 1/0.3 mm (a 1 mm lumen), until the re-probe throws it back; and a
  // stick spring weaker than f / rho lets it swing across the plane's tangent every iteration.
  bool curved_wall_gap = true;
  double buckling_seed_mm = 1.0e-2;        // lateral imperfection added to a compressed rod
  // ... once an edge is compressed by this strain: 50 mN at the default EA (5,000 N), about the
  // Euler load of a 200 mm span of a 0.014" wire (4 pi^2 EI / L^2 = 39 mN). At 5e-4 (2.5 N) a
  // wire folded in one plane stayed there to 1.8 N at the hand and snapped from the flat buckle to
  // the helix (docs/sim-tool/convergence.md, "The flat buckle's snaps").
  double buckling_strain = 1.0e-5;
};

}  // namespace cathbox::tool

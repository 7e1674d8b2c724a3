#include "tool/simulator.hpp"

#include "background_job.hpp"
#include "simulator_tuning.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {
constexpr double kTipProbeRange_mm = 20.0;
// Coils and the catheter tips they touch: pairs within this margin are gathered, and a node
// moves at most half of it per iteration, so no loop passes through another between gathers.
constexpr double kRodContactMargin_mm = 0.1;
constexpr double kRodContactStep_mm = 0.04;
// A coil's wall and rod-rod penalty, a tenth of the default: a soft coil (EI 0.02 N mm^2, loop
// forces of a few mN) ends steps with its contacts a few micrometres from settled; at 2e5 mN/mm
// each micrometre read as 200 mN. Penetration stays held to 5 % of its radius by projection.
constexpr double kCoilContactStiffness_mN_per_mm = 2.0e4;

// A catheter run directly in a balloon guide (the stent-retriever stacks' microcatheter) is
// steered by the wire it carries while advanced, as an aspiration stack's microcatheter is
// (tool::steer_aspiration_catheters): unsteered and sub-stepped, the M1 stent case's left the
// wire for a side branch at 30 s (convergence.md, "The stent retriever's microcatheter
// sub-stepped").
void steer_catheters_in_balloon_guides(std::span<const ToolSpec> tools, std::vector<ToolSpec>& specs) {
  for (std::size_t i = 0; i < tools.size(); ++i) {
    const ToolSpec& t = tools[i];
    if (t.kind != ToolKind::kCatheter || t.inside.empty() || specs[i].steered_by_inner != InnerSteering::kNone) continue;
    const auto guide = std::find_if(tools.begin(), tools.end(), [&t](const ToolSpec& g) { return g.name == t.inside; });
    if (guide == tools.end() || !guide->balloon.present() || !guide->inside.empty()) continue;
    specs[i].steered_by_inner = InnerSteering::kWhileAdvanced;
  }
}

// A guidewire that is not a stent's push wire (the wire whose clamp may hinge at its catheter's tip).
bool plain_guidewire(const ToolSpec& s) { return s.kind == ToolKind::kGuidewire && !s.stent.present(); }
}  // namespace

Simulator::Simulator(const WallModel& wall, std::span<const ToolSpec> tools, const Entry& entry,
                     const RodSettings& settings)
    : wall_(&wall), entry_(entry), settings_(settings), contacts_(kRodContactMargin_mm), released_turn_(tuning::kReleasedCoilTicks) {
  const std::size_t n = tools.size();
  rods_.reserve(n);
  std::size_t max_nodes = 0;
  for (const ToolSpec& spec : tools) {
    rods_.emplace_back(spec, settings);
    rods_.back().set_entry(entry.point_mm, entry.direction);
    max_nodes = std::max(max_nodes, rods_.back().node_total());
  }
  outer_of_.assign(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    if (tools[i].inside.empty()) continue;
    const std::size_t j = find_tool(tools[i].inside);
    if (j < n && j != i) outer_of_[i] = j;
  }
  // Nesting depth of each tool (a cycle, which the case parser refuses, is cut).
  std::vector<std::size_t> depth(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t d = 0;
    for (std::size_t o = outer_of_[i]; o < n && d <= n; o = outer_of_[o]) ++d;
    if (d > n) outer_of_[i] = n, d = 0;
    depth[i] = d;
  }
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) order_[i] = i;
  std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return depth[a] < depth[b]; });
  // Coils and the catheters they leave move in small iterations (no loop through another).
  for (std::size_t i = 0; i < n; ++i) {
    if (tools[i].kind == ToolKind::kCoil) apply_coil_settings(i);
  }
  specs_.assign(tools.begin(), tools.end());
  loaded_.assign(n, 0);
  insertion_.assign(n, 0.0);
  rotation_.assign(n, 0.0);
  stepped_depth_.assign(n, 0.0);
  stepped_rotation_.assign(n, 0.0);
  stepped_insertion_.assign(n, 0.0);
  moved_mm_.assign(n, 0.0);
  turned_rad_.assign(n, 0.0);
  removed_mm_.assign(n, 0.0);
  free_start_.assign(n, 0.0);
  carrier_.assign(n, n);
  tip_segment_.assign(n, -1);
  tip_hint_.assign(n, WallHint{});
  extra_ei_.assign(max_nodes, 0.0);
  sheath_.assign(n, SheathFriction{});
  sheath_result_.assign(n, SheathFriction::Result{});
  hand_force_.assign(n, 0.0);
  hand_torque_.assign(n, 0.0);
  converged_law_.assign(n, std::nullopt);
  held_.assign(n, 0);
  valve_.assign(n, ValveFriction{});
  valve_result_.assign(n, ValveFriction::Result{});
  coupling_next_.resize(n);
  coupling_set_.assign(n, IndexRange{});
  tip_push_.assign(n, glm::dvec3(0.0));
  push_slew_.assign(n, PushSlew{});
  converged_clamp_.assign(n, glm::dvec3(0.0));
  for (std::size_t i = 0; i < n; ++i) coupling_next_[i].assign(rods_[i].node_total(), glm::dvec3(0.0));
  balloons_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (tools[i].balloon.present()) {
      const double shaft = 2.0 * rods_[i].radius_at_mm(tools[i].balloon.from_tip_mm + 0.5 * tools[i].balloon.length_mm);
      balloons_[i].emplace(tools[i].balloon, shaft);
      specs_[i].steered_by_inner = InnerSteering::kAlways;
    }
  }
  steer_catheters_in_balloon_guides(tools, specs_);
  for (std::size_t i = 0; i < n; ++i) rods_[i].settings().clamp_hinge_at_entry = hinged_at_entry(i);
  stents_.resize(n);
  tip_grip_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!tools[i].stent.present()) continue;
    stents_[i].emplace(tools[i].stent, rods_[i].node_total());
    rods_[i].set_distal_friction(tools[i].stent.length_mm, kStentWallFriction);
    rods_[i].settings().contact_stiffness_mN_per_mm = std::min(rods_[i].settings().contact_stiffness_mN_per_mm, kStentContactStiffness_mN_per_mm);
  }
  detached_.reserve(16);
  parting_s_.assign(n, -1.0);
  path_.reserve(max_nodes * 2);
}

void Simulator::apply_coil_settings(std::size_t i) {
  rods_[i].settings().max_node_step_mm = std::min(rods_[i].settings().max_node_step_mm, kRodContactStep_mm);
  rods_[i].settings().contact_stiffness_mN_per_mm = kCoilContactStiffness_mN_per_mm;
  rods_[i].settings().linearised_clamp = true;
  rods_[i].settings().arc_predictor = true;
  // A coil pushed at a steady rate moves as it did the step before: the whole last motion is the
  // better start (BM_StepCoilDeploy: 6.7 -> 5.4 Newton iterations a step).
  rods_[i].settings().warm_start = 1.0;
  // A coil keeps the flat plane: its loops meet the sac's wall and each other far more than a
  // lumen curving round them (measured with the curved gap: released coils 0.18 / 0.13 ->
  // 0.43 / 0.91 % unconverged in the bundled coiling run).
  rods_[i].settings().curved_wall_gap = false;
  // ... and its stick spring on walls from its own contact stiffness (stick_stiffness_ratio), not the
  // tissue's shear: with the tissue's (171 mN/mm under a 0.25 mm coil, 12x softer) a released coil's
  // node settled 0.021 mm (16 % of its radius) out of the sac's lumen in
  // Coiling.SecondCoilPacksAgainstTheFirstInTheBundledSac; the sac wall's friction is not validated.
  rods_[i].settings().wall_shear_mN_per_mm2 = 0.0;
  if (outer_of_[i] < rods_.size()) {
    RodSettings& s = rods_[outer_of_[i]].settings();
    s.max_node_step_mm = std::min(s.max_node_step_mm, kRodContactStep_mm);
  }
}

std::size_t Simulator::find_tool(std::string_view name) const {
  for (std::size_t i = 0; i < rods_.size(); ++i) {
    if (rods_[i].spec().name == name) return i;
  }
  return rods_.size();
}

void Simulator::select(std::size_t tool) {
  if (tool < rods_.size()) active_ = tool;
}

double Simulator::max_insertion_mm(std::size_t tool) const {
  return rods_[tool].max_insertion_mm() + removed_mm_[tool];
}

void Simulator::set_insertion(std::size_t tool, double insertion_mm) {
  if (tool >= rods_.size() || !std::isfinite(insertion_mm)) return;
  insertion_[tool] = std::clamp(insertion_mm, 0.0, max_insertion_mm(tool));
}

void Simulator::set_rotation(std::size_t tool, double rotation_rad) {
  if (tool >= rods_.size() || !std::isfinite(rotation_rad)) return;
  rotation_[tool] = rotation_rad;
}

double Simulator::tip_depth_mm(std::size_t tool) const {
  return std::clamp(insertion_[tool] - removed_mm_[tool], 0.0, rods_[tool].max_insertion_mm());
}

bool Simulator::nested_in(std::size_t inner, std::size_t outer) const {
  const std::size_t n = rods_.size();
  for (std::size_t o = outer_of_[inner], guard = 0; o < n && guard <= n; o = outer_of_[o], ++guard) {
    if (o == outer) return true;
  }
  return false;
}

void Simulator::update_chain() {
  // A tool's own part starts at the furthest tip of the catheters around it; the catheter
  // owning that tip carries its entry.
  const std::size_t n = rods_.size();
  for (const std::size_t t : order_) {
    const std::size_t o = outer_of_[t];
    if (o >= n) {
      free_start_[t] = 0.0;
      carrier_[t] = n;
      continue;
    }
    const double tip_o = tip_depth_mm(o);
    if (tip_o > free_start_[o]) {
      free_start_[t] = tip_o;
      carrier_[t] = o;
    } else {
      free_start_[t] = free_start_[o];
      carrier_[t] = carrier_[o];
    }
    if (free_start_[t] <= 0.0) carrier_[t] = n;
  }
}

glm::dvec3 Simulator::path_point(std::size_t tool, double depth_mm) const {
  // The centre line a tool lies on at a depth: the free part of the catheter that holds it.
  const std::size_t n = rods_.size();
  if (depth_mm <= 0.0) return entry_.point_mm + entry_.direction * depth_mm;
  if (depth_mm > free_start_[tool]) {
    return rods_[tool].point_at_depth(depth_mm - free_start_[tool], nullptr, nullptr);
  }
  for (std::size_t c = outer_of_[tool], guard = 0; c < n && guard <= n; c = outer_of_[c], ++guard) {
    if (depth_mm > free_start_[c] && depth_mm <= tip_depth_mm(c)) {
      return rods_[c].point_at_depth(depth_mm - free_start_[c], nullptr, nullptr);
    }
  }
  return entry_.point_mm + entry_.direction * depth_mm;
}

void Simulator::prepare(std::size_t t) {
  const std::size_t n = rods_.size();
  Rod& rod = rods_[t];
  const double tip = tip_depth_mm(t);
  if (outer_of_[t] < n) {
    const std::size_t c = carrier_[t];
    if (c < n) {
      const Rod& carrier = rods_[c];
      const TipPose pose = carrier.tip();
      rod.move_entry(pose.position_mm, pose.direction, carrier.reference_director(carrier.node_total() - 2));
    } else {
      rod.move_entry(entry_.point_mm, entry_.direction, glm::dvec3(0.0));
    }
    rod.set_material_advance(tip - stepped_depth_[t]);
  }
  rod.set_boundary(std::max(0.0, tip - free_start_[t]), rotation_[t]);

  // Composite stiffness: every tool inside this one, where it lies on this one's free part.
  const std::size_t nodes = rod.node_total();
  const std::size_t window = std::min(rod.first_node(), nodes);
  std::fill(extra_ei_.begin() + static_cast<std::ptrdiff_t>(window), extra_ei_.begin() + static_cast<std::ptrdiff_t>(nodes), 0.0);
  bool any = false;
  const Rod* leader = nullptr;
  double leader_insertion = 0.0;
  for (std::size_t u = 0; u < n; ++u) {
    if (u == t || !nested_in(u, t)) continue;
    any = true;
    const double tip_u = tip_depth_mm(u);
    // Each node takes the inner tool's mean EI over its Voronoi region, the part past the inner
    // tool's tip counting nothing: as the inner tool slides, its tip and its section boundaries
    // change this one's stiffness by the length slid, not a node's worth in one tick (a pusher's
    // end drawn back through a microcatheter's 1 N mm^2 tip took 10 N mm^2 off a node at once).
    for (std::size_t k = std::max<std::size_t>(window, 1); k < nodes; ++k) {
      const double depth = free_start_[t] + rod.node_depth_mm(k);
      const double lo = depth - 0.5 * (rod.node_depth_mm(k) - rod.node_depth_mm(k - 1));
      const double hi = k + 1 < nodes ? depth + 0.5 * (rod.node_depth_mm(k + 1) - rod.node_depth_mm(k)) : depth;
      if (depth > 0.0 && lo < tip_u && hi > lo) {
        extra_ei_[k] += rods_[u].bending_integral_Nmm3(tip_u - hi, tip_u - lo) / (hi - lo);
      }
    }
    // A catheter advanced over a tool whose own part starts at this one's tip follows it.
    if (carrier_[u] == t && tip_u > free_start_[u] && leader == nullptr) {
      leader = &rods_[u];
      leader_insertion = tip_u - free_start_[t];
    }
  }
  if (any) rod.set_extra_bending(window, std::span<const double>(extra_ei_.data() + window, nodes - window));
  rod.set_leader(leader, leader_insertion);

  // Loads from the tools inside (their friction and their push on the bends).
  rod.clear_coupling_loads();
  const std::vector<glm::dvec3>& loads = coupling_next_[t];
  const IndexRange& loaded = coupling_set_[t];
  for (std::size_t k = loaded.begin_in(loads.size()); k < loaded.end_in(loads.size()) && k < nodes; ++k) {
    if (loads[k] != glm::dvec3(0.0)) rod.add_coupling_load(k, loads[k]);
  }
  if (tip_push_[t] != glm::dvec3(0.0)) rod.add_coupling_load(nodes - 1, tip_push_[t]);
}

// The clamp's hinge at the entry point (RodSettings::clamp_hinge_at_entry) for a tool alone in
// the body, held by the introducer's valve, for every catheter (balloon catheters included), for
// a coil (but while its joint or pusher is the clamp node: Rod::update_window), and for a
// guidewire in a catheter its inner tools steer, but a stent retriever's push wire: that
// catheter's tip yields to the hinged wire's stronger moment (its push bounded, push_bounded).
// A coil's node crossings at its microcatheter's tip went with it (the bundled coiling run's 2
// over 100 mN a tick; convergence.md, "Coils hinged at the entry").
// A wire in an unsteered catheter keeps it at the clamp node: the M1 Solumbra run's
// microwire (its microcatheter unsteered until record format 36), hinged at that tip while it was advanced over
// it, read 26-490 N of clamp force and was unconverged on 0.59 % of its ticks (convergence.md,
// "The clamp's hinge at the entry point", "Catheters hinged at the entry" and "Wires hinged in
// the catheters they steer"), but while its hand draws it back (drawn_back_wire).
bool Simulator::hinged_at_entry(std::size_t t) const {
  const ToolSpec& s = specs_[t];
  if (lone(t) || is_catheter(s.kind) || s.kind == ToolKind::kCoil) return true;
  const std::size_t o = outer_of_[t];
  return plain_guidewire(s) && o < rods_.size() && specs_[o].steered_by_inner != InnerSteering::kNone;
}

// A guidewire in a catheter (not a stent's push wire) that its hand draws back this step bends
// from that catheter's tip too (Rod::hinge_while_drawn_back, taken at node crossings only, so it
// never moves a clamp that holds still): drawn back at its clamp node, the dense coiling run's
// microwire bent at each node crossing of its microcatheter's tip, up to 386 mN on the hand in a
// tick (17 ticks over 100 mN; 3 hinged: convergence.md, "A wire drawn back bends from its
// catheter's tip"). Not while the catheter is advanced over it: that lost the Solumbra runs.
bool Simulator::drawn_back_wire(std::size_t t) const {
  return plain_guidewire(specs_[t]) && outer_of_[t] < rods_.size() && insertion_[t] < stepped_insertion_[t] - 1e-9;
}

// A balloon catheter's tip (steered by what it carries even parked, InnerSteering::kAlways), and
// the tip of a catheter with a wire hinged at it (hinged_at_entry, or drawn back), take that push changed by at
// most tuning::kTipPushSlew_mN a step: a one-tick wall touch of the inner tool's short free part
// beyond the tip (its clamp 700-850 mN across the tip) no longer lands a tenth of itself on the
// tip at once, throwing the tip off the touch and that free part back onto the wall some ticks
// later (the ADAPT run's balloon guide; convergence.md, "The balloon guide's steering push
// bounded"), and the hinged wire's clamp does not steer its catheter's tip into the M1 accesses'
// crease (23.0 s). Not on a catheter that carries only catheters and is steered while advanced:
// bounded there too, the M1 Solumbra run's parked microcatheter was left unconverged on 21 % of its
// ticks (0.24 % unbounded); but while a tool leaving its tip is drawn back into it
// (drawn_back_into): the ADAPT run's microcatheter drawn back into its parked aspiration catheter
// on ~1 N of clamp force moved the hand 115.3 mN in a tick unbounded, 99.2 mN bounded
// (convergence.md, "The lumen's bending push from the change of the moment").
// While a tool is drawn back into it the bound adapts to the push's own reversals (limit_tip_push):
// the free part shortens, its lateral stiffness (3 EI / l^3) rises past what a lagged push can
// follow, and the push swung at the bound every tick (convergence.md, "The steering push's slew
// halved at its reversals").
bool Simulator::push_bounded(std::size_t c) const {
  if (specs_[c].steered_by_inner == InnerSteering::kAlways || drawn_back_into(c)) return true;
  for (std::size_t u = 0; u < rods_.size(); ++u) {
    if (outer_of_[u] != c || specs_[u].kind != ToolKind::kGuidewire) continue;
    if (rods_[u].settings().clamp_hinge_at_entry || drawn_back_wire(u)) return true;
  }
  return false;
}

void Simulator::limit_tip_push() {
  for (std::size_t t = 0; t < tip_push_.size(); ++t) {
    PushSlew& slew = push_slew_[t];
    if (!push_bounded(t)) {
      slew = PushSlew{};
      continue;
    }
    glm::dvec3 change = tip_push_[t] - tip_push_before_[t];
    if (!drawn_back_into(t)) slew.share = 1.0;
    else if (glm::dot(change, slew.last) < 0.0) slew.share = std::max(slew.share * tuning::kPushSlewDown, tuning::kPushSlewFloor);
    else slew.share = std::min(slew.share * tuning::kPushSlewUp, 1.0);
    const double most = tuning::kTipPushSlew_mN * slew.share;
    const double length = glm::length(change);
    if (length > most) {
      change *= most / length;
      tip_push_[t] = tip_push_before_[t] + change;
    }
    slew.last = change;
  }
}

// Tool t's solve in the step, after the tools it runs in; `released`: coils are released.
void Simulator::solve_tool(std::size_t t, double dt_s, bool released) {
  const std::size_t n = rods_.size();
  prepare(t);
  update_contact_members();
  const bool member = std::any_of(members_.begin(), members_.end(),
                                  [&](const RodContactField::Member& m) { return m.rod == &rods_[t]; });
  // An unconverged tick solved again in sub-increments (Simulator::substepped).
  // A guidewire, and a catheter directly in a balloon guide (the ADAPT pass), in up to
  // tuning::kFineSubsteps.
  const bool guided = outer_of_[t] < n && balloon_guide(outer_of_[t]) && specs_[t].kind == ToolKind::kCatheter;
  const bool fine = guided || specs_[t].kind == ToolKind::kGuidewire;
  const int most = fine ? tuning::kFineSubsteps : tuning::kLoneToolSubsteps;
  rods_[t].settings().substeps_max = substepped(t) ? most : 1;
  rods_[t].step(dt_s, *wall_, member ? &contacts_ : nullptr);
  if (observer_ != nullptr) observer_->solved(false, t, rods_[t]);
  if (released) sleep_.tool_solved(t, rods_, coil_views_, contacts_.margin_mm());
  WallProbe probe;
  probe.center_mm = rods_[t].tip().position_mm;
  probe.range_mm = kTipProbeRange_mm;
  WallContact c;
  if (insertion_[t] > 0.0 && wall_->probe(probe, tip_hint_[t], c)) tip_segment_[t] = c.segment;
  else if (insertion_[t] <= 0.0) tip_segment_[t] = -1;
}

void Simulator::step(double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) dt_s = 1e-3;
  settle();  // the last step's released coils, if it left their job running (released_overlap)
  if (before_solves_) before_solves_();
  if (observer_ != nullptr) observer_->step_begins();
  const std::size_t n = rods_.size();
  update_chain();
  update_balloons(dt_s);
  update_stents();
  update_tip_grips();
  advance_partings(dt_s);
  const bool released = !detached_.empty();
  if (released && balloon_moved_) sleep_.wake_all();  // a balloon's diameter moved (coils may rest on it)
  if (released) sleep_.begin(rods_, detached_);
  for (std::size_t t = 0; t < n; ++t) rods_[t].hinge_while_drawn_back(drawn_back_wire(t));
  if (released) launch_released(dt_s);
  for (const std::size_t t : order_) solve_tool(t, dt_s, released);
  if (released) {
    pending_ = true;
    launched_step_ = steps_;
    if (!overlap_) finish_released();
  }
  // Friction in the lumens, felt at the hands, and its reaction on the catheters.
  tip_push_before_ = tip_push_;  // same size after the first step: no allocation
  for (std::size_t t = 0; t < n; ++t) {
    std::vector<glm::dvec3>& next = coupling_next_[t];
    for (std::size_t k = coupling_set_[t].begin_in(next.size()); k < coupling_set_[t].end_in(next.size()); ++k) {
      next[k] *= 1.0 - tuning::kCouplingRelaxation;
    }
    if (!tip_lean_held(t)) tip_push_[t] *= 1.0 - tuning::kTipPushRelaxation;
  }
  for (const std::size_t t : order_) {
    if (outer_of_[t] < n) {
      update_sheath(t, dt_s);
    } else {
      hand_force_[t] = rods_[t].hand_force_mN();
      hand_torque_[t] = rods_[t].hand_torque_mNmm();
    }
  }
  limit_tip_push();
  // The haemostatic valves: each tool's, moving with what it slides through (the patient, or
  // the hub of its catheter, which feels the reaction).
  const double k_anchor = settings_.stick_stiffness_mN_per_mm();
  for (std::size_t t = 0; t < n; ++t) {
    const std::size_t o = outer_of_[t];
    const double through = insertion_[t] - (o < n ? insertion_[o] : 0.0);
    const double turn = rotation_[t] - (o < n ? rotation_[o] : 0.0);
    const Rod& rod = rods_[t];
    const double radius = rod.radius_at_mm(std::clamp(insertion_[t], 0.0, rod.length_mm()));
    valve_result_[t] = valve_[t].update(through, turn, insertion_[t] > 0.0, rod.spec().valve_friction(), radius, k_anchor);
    hand_force_[t] += valve_result_[t].force_mN;
    hand_torque_[t] += valve_result_[t].torque_mNmm;
    if (o < n) {
      hand_force_[o] -= valve_result_[t].force_mN;
      hand_torque_[o] -= valve_result_[t].torque_mNmm;
    }
  }
  hold_unconverged();
  for (std::size_t t = 0; t < n; ++t) {
    stepped_depth_[t] = tip_depth_mm(t);
    moved_mm_[t] = insertion_[t] - stepped_insertion_[t];
    turned_rad_[t] = rotation_[t] - stepped_rotation_[t];
    stepped_insertion_[t] = insertion_[t];
    stepped_rotation_[t] = rotation_[t];
  }
  time_s_ += dt_s;
  ++steps_;
}

double Simulator::hand_force_mN(std::size_t tool) const { return hand_force_[tool]; }
double Simulator::hand_torque_mNmm(std::size_t tool) const { return hand_torque_[tool]; }

const WallModel* Simulator::swap_wall(const WallModel& next) {
  settle();
  const WallModel* old = wall_;
  wall_ = &next;
  for (Rod& rod : rods_) rod.forget_wall();
  for (Rod& coil : detached_) coil.forget_wall();
  sleep_.wake_all();
  for (WallHint& h : tip_hint_) h = WallHint{};
  ++wall_swaps_;
  return old;
}

}  // namespace cathbox::tool

// The simulator's devices: coil detachment and loading, balloon inflation, and their per-step updates.
#include "tool/simulator.hpp"

#include "simulator_tuning.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {
constexpr double kBalloonGripFriction = 0.3;  // balloon on the intima (inflated)
}  // namespace

const char* device_error_text(DeviceError e) {
  switch (e) {
    case DeviceError::kNone: return "ok";
    case DeviceError::kNoSuchTool: return "no such tool";
    case DeviceError::kNotACoil: return "the tool carries no coil to detach";
    case DeviceError::kCoilInCatheter: return "the coil's detachment zone is still inside the catheter";
    case DeviceError::kNotABalloon: return "the tool has no balloon";
    case DeviceError::kOutOfRange: return "pressure or volume out of range";
    case DeviceError::kCoilAttached: return "the loaded coil is not detached yet";
    case DeviceError::kNoNextCoil: return "the case lists no further coil for this tool";
  }
  return "unknown";
}

bool Simulator::carries_attached_coil(std::size_t tool) const {
  return tool < rods_.size() && rods_[tool].spec().kind == ToolKind::kCoil && rods_[tool].spec().detach_mm > 0.0 &&
         !(removed_mm_[tool] > 0.0);
}

bool Simulator::has_next_coil(std::size_t tool) const {
  return tool < rods_.size() && rods_[tool].spec().kind == ToolKind::kCoil && loaded_[tool] < specs_[tool].next_coils.size();
}

DeviceError Simulator::detach(std::size_t tool) {
  if (tool >= rods_.size()) return DeviceError::kNoSuchTool;
  if (!carries_attached_coil(tool)) return DeviceError::kNotACoil;
  if (parting(tool)) return DeviceError::kNone;  // already parting
  // The detachment zone must have left the catheter (its marker past the catheter's tip).
  if (!zone_out(tool) || !rods_[tool].soften_joint(rods_[tool].spec().detach_mm, 1.0)) return DeviceError::kCoilInCatheter;
  parting_s_[tool] = 0.0;
  return DeviceError::kNone;
}

bool Simulator::parting(std::size_t tool) const { return tool < parting_s_.size() && parting_s_[tool] >= 0.0; }

bool Simulator::zone_out(std::size_t tool) const {
  return tip_depth_mm(tool) - free_start_[tool] >= rods_[tool].spec().detach_mm + 1e-6;
}

// A detachment zone does not part in an instant: an electrolytic zone dissolves, a thermal one
// melts. Its section shrinking at a steady rate, the bending and twisting stiffness of the joint
// between coil and pusher (EI, GJ ~ r^4) fall as (1 - t / T)^4 of their built values, and the
// coil is released at T = tuning::kDetachParting_s, its joint by then carrying no moment. What
// the pusher held its coil with at the junction (the coil bent out of the catheter's tip: the
// bundled coiling run's +201 / +167 mN at the hand) so leaves the hand as the zone parts, not in
// one tick (-276.9 / -233.5 mN at 26.800 / 39.500 s when the release was instant). A zone drawn
// back into the catheter before it parts stays whole, its joint restored (an electrolytic zone
// dissolves only in the blood). The axial push through the joint is carried whole until the
// release (its edges keep their stiffness: a softened edge would fold into the pusher).
void Simulator::advance_partings(double dt_s) {
  for (std::size_t t = 0; t < parting_s_.size(); ++t) {
    if (!parting(t)) continue;
    Rod& rod = rods_[t];
    if (!zone_out(t)) {
      rod.soften_joint(rod.spec().detach_mm, 1.0);
      parting_s_[t] = -1.0;
      continue;
    }
    parting_s_[t] += dt_s;
    const double left = std::max(0.0, 1.0 - parting_s_[t] / tuning::kDetachParting_s);
    rod.soften_joint(rod.spec().detach_mm, left * left * left * left);
    if (left <= 0.0) release_coil(t);
  }
}

// The parted zone: the coil becomes a free rod, the pusher keeps the proximal part.
void Simulator::release_coil(std::size_t tool) {
  parting_s_[tool] = -1.0;
  Rod& rod = rods_[tool];
  const double length = rod.spec().detach_mm;
  Rod coil = rod.split_distal(length);
  if (coil.node_total() == 0) {  // not a vertex (detach checked it is): the joint stays whole
    rod.soften_joint(length, 1.0);
    return;
  }
  removed_mm_[tool] += length;
  stepped_depth_[tool] = tip_depth_mm(tool);
  coupling_next_[tool].resize(rod.node_total());
  coil.settings().warm_start = tuning::kReleasedCoilWarmStart;
  detached_.push_back(std::move(coil));
  coil_views_.push_back(Rod::contact_view_of(detached_.back()));
  coil_views_.back().mirror_published_view(detached_.back());
  // The field's members point at the rods: the pusher is shorter and detached_ may have moved.
  update_contact_members();
}

DeviceError Simulator::load_next_coil(std::size_t tool) {
  if (tool >= rods_.size()) return DeviceError::kNoSuchTool;
  settle();  // a new rod: the field's members change
  if (rods_[tool].spec().kind != ToolKind::kCoil) return DeviceError::kNotACoil;
  if (!(removed_mm_[tool] > 0.0)) return DeviceError::kCoilAttached;
  if (!has_next_coil(tool)) return DeviceError::kNoNextCoil;
  // The old pusher is out (withdrawn through the hub); the next coil enters at the hub.
  const ToolSpec spec = with_next_coil(specs_[tool], loaded_[tool]);
  ++loaded_[tool];
  rods_[tool] = Rod(spec, settings_);
  rods_[tool].set_entry(entry_.point_mm, entry_.direction);
  apply_coil_settings(tool);
  rods_[tool].settings().clamp_hinge_at_entry = hinged_at_entry(tool);
  insertion_[tool] = 0.0;
  rotation_[tool] = 0.0;
  stepped_depth_[tool] = 0.0;
  stepped_rotation_[tool] = 0.0;
  stepped_insertion_[tool] = 0.0;
  moved_mm_[tool] = 0.0;
  turned_rad_[tool] = 0.0;
  removed_mm_[tool] = 0.0;
  tip_segment_[tool] = -1;
  tip_hint_[tool] = WallHint{};
  sheath_[tool] = SheathFriction{};
  sheath_result_[tool] = SheathFriction::Result{};
  valve_[tool] = ValveFriction{};
  valve_result_[tool] = ValveFriction::Result{};
  hand_force_[tool] = 0.0;
  hand_torque_[tool] = 0.0;
  converged_law_[tool].reset();
  held_[tool] = 0;
  coupling_next_[tool].assign(rods_[tool].node_total(), glm::dvec3(0.0));
  coupling_set_[tool] = IndexRange{};
  tip_push_[tool] = glm::dvec3(0.0);
  push_slew_[tool] = PushSlew{};
  converged_clamp_[tool] = glm::dvec3(0.0);
  if (extra_ei_.size() < rods_[tool].node_total()) extra_ei_.resize(rods_[tool].node_total(), 0.0);
  update_chain();
  update_contact_members();  // the field listed the old pusher's nodes
  return DeviceError::kNone;
}

DeviceError Simulator::inflate_pressure(std::size_t tool, double pressure_atm) {
  if (tool >= rods_.size()) return DeviceError::kNoSuchTool;
  if (!balloons_[tool]) return DeviceError::kNotABalloon;
  if (!std::isfinite(pressure_atm) || pressure_atm < 0.0 || pressure_atm > Balloon::kMaxPressure_atm) {
    return DeviceError::kOutOfRange;
  }
  balloons_[tool]->set_target_pressure(pressure_atm);
  return DeviceError::kNone;
}

DeviceError Simulator::inflate_volume(std::size_t tool, double volume_ml) {
  if (tool >= rods_.size()) return DeviceError::kNoSuchTool;
  if (!balloons_[tool]) return DeviceError::kNotABalloon;
  if (!std::isfinite(volume_ml) || volume_ml < 0.0 ||
      volume_ml > balloons_[tool]->volume_at(Balloon::kMaxPressure_atm)) {
    return DeviceError::kOutOfRange;
  }
  balloons_[tool]->set_target_volume(volume_ml);
  return DeviceError::kNone;
}

DeviceError Simulator::deflate(std::size_t tool) {
  if (tool >= rods_.size()) return DeviceError::kNoSuchTool;
  if (!balloons_[tool]) return DeviceError::kNotABalloon;
  balloons_[tool]->deflate();
  return DeviceError::kNone;
}

const Balloon* Simulator::balloon(std::size_t tool) const {
  return tool < balloons_.size() && balloons_[tool] ? &*balloons_[tool] : nullptr;
}

void Simulator::balloon_axis(std::size_t tool, std::vector<glm::dvec3>& points_mm) const {
  points_mm.clear();
  const Balloon* b = balloon(tool);
  if (b == nullptr) return;
  const Rod& rod = rods_[tool];
  const double lo = b->spec().from_tip_mm;
  const double hi = lo + b->spec().length_mm;
  points_mm.push_back(rod.point_at_from_tip(hi));
  for (std::size_t k = rod.first_node(); k < rod.node_total(); ++k) {
    const double s = rod.node_from_tip_mm(k);
    if (s > lo && s < hi) points_mm.push_back(rod.positions()[k]);
  }
  points_mm.push_back(rod.point_at_from_tip(lo));
}

// The per-step device updates: balloons, stents, the owner's tip grips.
void Simulator::update_balloons(double dt_s) {
  balloon_moved_ = false;
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    if (!balloons_[t]) continue;
    Balloon& b = *balloons_[t];
    const double before_atm = b.pressure_atm();
    b.step(dt_s);
    // Its diameter moves under the coils it touches: sleeping coils are solved again.
    balloon_moved_ = balloon_moved_ || b.pressure_atm() != before_atm;
    // An inflated balloon grips the wall: friction on its surface, pressed with the pressure.
    Rod& rod = rods_[t];
    const double lo = b.spec().from_tip_mm;
    const double hi = lo + b.spec().length_mm;
    const double pressure = b.inflated() ? b.pressure_atm() * Balloon::kAtm_N_per_mm2 : 0.0;
    for (std::size_t k = rod.first_free_node(); k < rod.node_total(); ++k) {
      const double s = rod.node_from_tip_mm(k);
      if (s < lo || s > hi) continue;
      const double h = k + 1 < rod.node_total() ? rod.node_from_tip_mm(k) - rod.node_from_tip_mm(k + 1)
                                                 : rod.node_from_tip_mm(k - 1) - rod.node_from_tip_mm(k);
      const double area = M_PI * b.diameter_mm() * h;
      rod.set_grip(k, kBalloonGripFriction * pressure * area * 1000.0);
    }
  }
}

// A stent out of its catheters expands and grips the wall (stent_retriever.hpp).
void Simulator::update_stents() {
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    if (stents_[t]) stents_[t]->update(rods_[t], *wall_);
  }
}

// The owner's grips on tool tips (set_tip_grip), on the tip node while it is free.
void Simulator::update_tip_grips() {
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    Rod& rod = rods_[t];
    const std::size_t tip = rod.node_total() - 1;
    // A stent's or a balloon's own grip holds that node.
    if (stents_[t] || (balloons_[t] && balloons_[t]->spec().from_tip_mm <= 0.0)) continue;
    rod.set_grip(tip, rod.first_free_node() <= tip ? tip_grip_[t] : 0.0);
  }
}

}  // namespace cathbox::tool

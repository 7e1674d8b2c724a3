// What the views read of a session: the snapshot published after each tick (the tools' nodes,
// contacts, the held tool's tip and hand force, the metrics, fluoroscopy and thrombectomy
// state), the contrast cells and the widened wall.
#include "session/session.hpp"

#include <algorithm>

namespace cathbox::session {
namespace {

glm::vec3 to_f(const glm::dvec3& v) { return glm::vec3(v); }

}  // namespace

// What does not change during a run, written once into every slot before the first tick (the
// tick's publish() leaves it alone): each tool's stent length and its push wire's radius (the
// narrowest node of the tool as built, before its stent expands), that the released coils are
// not held, the thrombectomy unit's first aspiration catheter and balloon guide.
void Session::prepare_snapshot(SceneSnapshot& s) const {
  const std::vector<tool::ToolSpec>& specs = scene_->spec.tools;
  const std::size_t tools = std::min({sim_->tool_count(), specs.size(), kMaxTools});
  for (std::size_t i = 0; i < tools; ++i) {
    if (!specs[i].stent.present()) continue;
    ToolView& tv = s.tools[i];
    tv.stent_length_mm = static_cast<float>(specs[i].stent.length_mm);
    const tool::Rod& rod = sim_->rod(i);
    double wire_mm = rod.node_total() > 0 ? rod.node_radius_mm(0) : 0.0;
    for (std::size_t k = 1; k < rod.node_total(); ++k) wire_mm = std::min(wire_mm, rod.node_radius_mm(k));
    tv.wire_radius_mm = static_cast<float>(wire_mm);
    tv.stent_carrier = sim_->outer_of(i) < tools ? static_cast<int>(sim_->outer_of(i)) : -1;
  }
  for (ToolView& cv : s.coils) cv.active = false;
  if (thrombectomy_) {
    const std::optional<std::size_t> a = thrombectomy_->first_aspirator();
    const std::optional<std::size_t> b = thrombectomy_->first_balloon_guide();
    s.aspiration_tool = a ? static_cast<int>(*a) : -1;
    s.balloon_guide_tool = b ? static_cast<int>(*b) : -1;
  }
}

void Session::publish() {
  SceneSnapshot& s = exchange_.write_slot();
  s.sim_time_us = tick_ * options_.period_us;
  s.tick = tick_;
  const std::size_t active = sim_->active_tool();
  s.held_tool = active;
  s.held_coil_attached = sim_->carries_attached_coil(active);
  s.held_coil_parting = sim_->parting(active);
  s.held_next_coil = !s.held_coil_attached && sim_->has_next_coil(active);
  // The snapshot lists the case's tools, then the released coils (copied within the reserved
  // capacity: publishing never allocates).
  const auto copy_nodes = [](const tool::ToolSnapshot& t, ToolView& tv) {
    tv.nodes_mm.clear();
    tv.frames.clear();
    const std::size_t n = std::min(t.positions_mm.size(), tv.nodes_mm.capacity());  // never allocate here
    for (std::size_t k = 0; k < n; ++k) {
      tv.nodes_mm.push_back(to_f(t.positions_mm[k]));
      tv.frames.push_back(k < t.normals.size() ? to_f(t.normals[k]) : glm::vec3(0.0F));
    }
    tv.radius_mm = t.radii_mm.empty() ? 0.2F : *std::max_element(t.radii_mm.begin(), t.radii_mm.end());
  };
  const std::size_t tools = std::min(sim_->tool_count(), snap_.tools.size());
  s.tool_count = static_cast<int>(std::min<std::size_t>(tools, SceneSnapshot::kMaxTools));
  s.contacts.clear();
  for (int i = 0; i < s.tool_count; ++i) {
    const tool::ToolSnapshot& t = snap_.tools[static_cast<std::size_t>(i)];
    ToolView& tv = s.tools[static_cast<std::size_t>(i)];
    tv.active = static_cast<std::size_t>(i) == active;
    copy_nodes(t, tv);
    if (const tool::StentRetriever* stent = sim_->stent(static_cast<std::size_t>(i))) {
      tv.stent_unsheathed_mm = static_cast<float>(stent->state().unsheathed_mm);
      tv.stent_retrieving = thrombectomy_ && thrombectomy_->stent_retrieving(static_cast<std::size_t>(i));
    }
    for (const tool::RodContact& c : t.contacts) {
      if (s.contacts.size() == SceneSnapshot::kMaxContacts) break;
      s.contacts.push_back({to_f(c.point_mm), static_cast<float>(c.normal_force_mN)});
    }
  }
  s.coil_count = static_cast<int>(std::min<std::size_t>(snap_.tools.size() - tools, SceneSnapshot::kMaxCoils));
  for (int i = 0; i < s.coil_count; ++i) {
    ToolView& cv = s.coils[static_cast<std::size_t>(i)];
    const tool::ToolSnapshot& coil = snap_.tools[tools + static_cast<std::size_t>(i)];
    copy_nodes(coil, cv);
    // The primary wind's radius: the node at the cut may carry the pusher's (a wider end node).
    if (!coil.radii_mm.empty()) cv.radius_mm = coil.radii_mm[coil.radii_mm.size() / 2];
  }
  if (active < snap_.tools.size()) {
    const tool::ToolSnapshot& held = snap_.tools[active];
    s.tip_mm = to_f(held.tip.position_mm);
    s.tip_direction = to_f(held.tip.direction);
    s.tip_up = to_f(held.tip.normal);
    s.insertion_mm = held.insertion_mm;
    s.rotation_rad = held.rotation_rad;
    s.hand_force_mN = held.hand_force_mN;
    s.hand_torque_mNmm = held.hand_torque_mNmm;
  }
  const HapticThread* t = active_thread();
  s.haptic_rate_hz = t ? t->rate_hz() : 0.0;
  s.haptic_ticks = tick_;
  s.dropped_ticks = t ? t->dropped() : 0;
  s.metrics = metrics_.metrics();
  // A real-time run's drops so far (the live frame's figure; the metrics take the total at the end).
  if (const std::optional<std::int64_t> dropped = real_time_drops(); dropped && !s.metrics.haptic_dropped_ticks) {
    s.metrics.haptic_dropped_ticks = dropped;
    s.metrics.haptic_ticks = tick_;
  }
  s.wall_force_mN = contacts_.wall_mN();
  if (fluoro_) fluoro_->publish(s.fluoro);
  s.run_over = over_.load(std::memory_order_relaxed);
  s.wall_generation = angioplasty_ ? angioplasty_->swap().generation() : 0;
  s.wall_pressure_kPa = wall_field_ ? wall_field_->pressure_kPa() : 0.0;
  if (thrombectomy_) publish_clots(s);
  exchange_.publish();
}

// A thrombectomy case's part of the snapshot: the pump, the flow arrest, the clots and the emboli
// in transit (within the snapshot's room), the clots removed.
void Session::publish_clots(SceneSnapshot& s) const {
  s.aspirating = s.aspiration_tool >= 0 && thrombectomy_->aspirating(static_cast<std::size_t>(s.aspiration_tool));
  s.flow_arrest = thrombectomy_->arrested();
  s.clot_count = static_cast<int>(std::min<std::size_t>(thrombectomy_->clots().size(), SceneSnapshot::kMaxClots));
  for (int k = 0; k < s.clot_count; ++k) s.clots[static_cast<std::size_t>(k)] = thrombectomy_->clot_view(static_cast<std::size_t>(k));
  for (std::size_t k = 0; k < thrombectomy_->emboli_in_transit() && s.clot_count < SceneSnapshot::kMaxClots; ++k) {
    s.clots[static_cast<std::size_t>(s.clot_count++)] = thrombectomy_->embolus_view(k);
  }
  s.clots_removed = thrombectomy_->clots_removed();
}

const std::vector<FluoroCell>& Session::fluoro_cells() const {
  static const std::vector<FluoroCell> kNone;
  return fluoro_ ? fluoro_->cells() : kNone;
}

std::shared_ptr<const tool::WallSurface> Session::wall_surface() const {
  if (!angioplasty_ || angioplasty_->swap().generation() == 0) return {};
  return angioplasty_->swap().surface();
}

}  // namespace cathbox::session

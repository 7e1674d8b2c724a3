// The thrombectomy unit's controls and where they act in the flow: the vacuum switched on and
// off (the catheter's open tip a sink of the network while it draws, its mouth), the balloon
// guide inflated and deflated (a flow arrest on its tip's segment). The rest of the unit:
// thrombectomy_unit.cpp (clots, passes, grading), thrombectomy_stent.cpp, thrombectomy_emboli.cpp.
#include <algorithm>
#include <string>

#include "flow/aspiration.hpp"
#include "session/thrombectomy_unit.hpp"

namespace cathbox::session {

std::vector<flow::AspirationSink> ThrombectomyUnit::live_sinks(std::vector<std::size_t>* tools) const {
  std::vector<flow::AspirationSink> out;
  for (const Aspirator& a : aspirators_) {
    if (aspirating_[a.tool] == 0 || hold_.on(a.tool) || a.tool >= tips_.size()) continue;
    const flow::CenterlinePosition at = locator_.nearest(tips_[a.tool]);
    if (at.distance_mm > locator_.radius_at(at.segment, at.arc_mm)) continue;  // not in a vessel (not inserted yet)
    const double r = flow::catheter_resistance_Pa_s_per_mm3(a.length_mm, a.inner_diameter_mm, network_.settings().viscosity_mPa_s);
    out.push_back({at.segment, at.arc_mm, flow::vacuum_Pa(a.source), r});
    if (tools != nullptr) tools->push_back(a.tool);
  }
  return out;
}

void ThrombectomyUnit::update_sinks(std::int64_t time_us) {
  if (aspirators_.empty()) return;
  std::vector<flow::AspirationSink> now = live_sinks();
  const auto node_of = [&](const flow::AspirationSink& s) { return network_.nearer_node(s.segment, s.arc_mm); };
  bool same = now.size() == sinks_.size();
  for (std::size_t k = 0; same && k < now.size(); ++k) same = node_of(now[k]) == node_of(sinks_[k]);
  if (same) return;
  sinks_ = std::move(now);
  (void)resolve(time_us, true);
}

flow::CenterlinePosition ThrombectomyUnit::mouth(std::size_t t) const {
  std::vector<std::size_t> tools;
  const std::vector<flow::AspirationSink> sinks = live_sinks(&tools);
  for (std::size_t k = 0; k < sinks.size(); ++k) {
    if (tools[k] != t) continue;
    const bool at_start = network_.nearer_node(sinks[k].segment, sinks[k].arc_mm) == network_.segments()[sinks[k].segment].start_node;
    return {sinks[k].segment, at_start ? 0.0 : locator_.length_mm(sinks[k].segment), 0.0};
  }
  return locator_.nearest(tips_[t]);
}

const Aspirator* ThrombectomyUnit::aspirator(std::size_t tool) const {
  const auto a = std::find_if(aspirators_.begin(), aspirators_.end(), [tool](const Aspirator& x) { return x.tool == tool; });
  return a == aspirators_.end() ? nullptr : &*a;
}

std::optional<std::size_t> ThrombectomyUnit::first_balloon_guide() const {
  const auto b = std::find(balloon_.begin(), balloon_.end(), std::uint8_t{1});
  return b == balloon_.end() ? std::nullopt : std::optional<std::size_t>(static_cast<std::size_t>(b - balloon_.begin()));
}

bool ThrombectomyUnit::apply(Control& c, ControlContext& ctx) {
  if (c.size != 2 || c.payload[1] > 1) return false;
  const bool on = c.payload[1] == 1;
  return c.kind == static_cast<std::uint16_t>(ControlKind::kAspiration) ? set_aspiration(c.payload[0], on, ctx.time_us)
                                                                         : set_balloon_guide(c.payload[0], on, ctx.time_us);
}

bool ThrombectomyUnit::set_aspiration(std::size_t t, bool on, std::int64_t time_us) {
  if (t >= tool_names_.size()) return false;
  const char* name = tool_names_[t].c_str();
  const Aspirator* a = aspirator(t);
  if (a == nullptr) {
    log(time_us, "aspiration: refused (the %s has no vacuum source)", name);
    return false;
  }
  if ((aspirating_[t] != 0) == on) return false;
  aspirating_[t] = on ? 1 : 0;
  if (on) {
    log(time_us, "aspiration on: the %s on the %s, %.3f N at its tip", name,
        std::string(flow::vacuum_source_name(a->source)).c_str(), flow::aspiration_force_N(a->source, a->inner_diameter_mm));
  } else if (hold_.on(t)) {
    log(time_us, "aspiration off: the %s lets the clot go (no pass)", name);
    hold_.release();
  } else {
    log(time_us, "aspiration off: the %s", name);
  }
  update_sinks(time_us);
  return true;
}

// A flow arrest on the segment of the catheter's tip.
bool ThrombectomyUnit::set_balloon_guide(std::size_t t, bool on, std::int64_t time_us) {
  if (t >= tool_names_.size()) return false;
  const char* name = tool_names_[t].c_str();
  if (balloon_[t] == 0) {
    log(time_us, "balloon guide: refused (the %s carries no balloon)", name);
    return false;
  }
  const auto held = std::find(arrest_tool_.begin(), arrest_tool_.end(), t);
  if ((held != arrest_tool_.end()) == on) return false;
  if (on) {
    if (t >= tips_.size()) return false;
    const flow::CenterlinePosition at = locator_.nearest(tips_[t]);
    if (at.distance_mm > 1.5 * locator_.radius_at(at.segment, at.arc_mm) + 1.0) {
      log(time_us, "balloon guide: refused (the %s's tip is outside the vessels)", name);
      return false;
    }
    arrests_.push_back({at.segment});
    arrest_tool_.push_back(t);
    ++figures_.balloon_guide_inflations;
    if (arrest_since_us_ < 0) arrest_since_us_ = time_us;
    log(time_us, "balloon guide inflated in the %s: flow arrest", segment_name(at.segment).c_str());
  } else {
    const auto k = static_cast<std::size_t>(held - arrest_tool_.begin());
    arrests_.erase(arrests_.begin() + static_cast<std::ptrdiff_t>(k));
    arrest_tool_.erase(held);
    if (arrests_.empty()) {
      arrest_before_us_ += time_us - arrest_since_us_;
      arrest_since_us_ = -1;
      figures_.flow_arrest_s = static_cast<double>(arrest_before_us_) * 1e-6;
    }
    log(time_us, "balloon guide of the %s deflated: flow restored", name);
  }
  return resolve(time_us, true);
}

}  // namespace cathbox::session

// Every tool's hand force against the box's limits (tool_forces.hpp).
#include "session/tool_forces.hpp"

#include <cmath>
#include <cstdio>

namespace cathbox::session {

void ToolForces::count(Tool& k, double f, std::int64_t time_us, bool fresh) const {
  if (std::abs(f) > k.peak_mN) k.peak_mN = std::abs(f), k.peak_us = time_us;
  if (std::abs(f) > box_.full_scale_mN) ++k.over_full_scale;
  if (k.seen && !fresh && time_us >= changes_from_us_) {
    const double change = std::abs(f - k.last_mN);
    if (change > k.largest_change_mN) k.largest_change_mN = change, k.change_us = time_us;
    if (change > slew_per_tick_mN()) ++k.over_slew;
  }
  k.last_mN = f;
  k.seen = true;
}

void ToolForces::observe(const TickView& v) {
  const tool::Simulator& sim = v.sim;
  if (tools_.size() < sim.tool_count()) tools_.resize(sim.tool_count());
  for (std::size_t t = 0; t < sim.tool_count(); ++t) {
    tools_[t].name = sim.rod(t).spec().name;
    count(tools_[t], sim.hand_force_mN(t), v.time_us, false);
  }
  const std::size_t h = v.input.held;
  if (h >= sim.tool_count()) return;
  bool fresh = !held_.seen || h != held_.tool;
  for (const Control& c : v.controls) fresh = fresh || c.kind == static_cast<std::uint16_t>(ControlKind::kLoadCoil);
  held_.tool = h;
  held_.fresh = fresh;
  count(held_, sim.hand_force_mN(h), v.time_us, fresh);
}

std::string ToolForces::format() const {
  std::string out;
  const auto line = [&](const char* name, const Tool& k) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "%-16s peak %8.1f mN at %8.3f s; largest change %7.1f mN/tick at %8.3f s; %lld ticks over %.0f mN/tick, "
                  "%lld over %.0f mN\n",
                  name, k.peak_mN, 1e-6 * static_cast<double>(k.peak_us), k.largest_change_mN,
                  1e-6 * static_cast<double>(k.change_us), static_cast<long long>(k.over_slew), slew_per_tick_mN(),
                  static_cast<long long>(k.over_full_scale), box_.full_scale_mN);
    out += text;
  };
  for (const Tool& k : tools_) line(k.name.c_str(), k);
  if (held_.seen) line("(held tool)", held_);
  return out;
}

}  // namespace cathbox::session

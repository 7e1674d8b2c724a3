// Every tool's hand force against the box's limits (tool_forces.hpp).
#include "session/tool_forces.hpp"

#include <cmath>
#include <cstdio>

namespace cathbox::session {

void ToolForces::observe(const TickView& v) {
  const tool::Simulator& sim = v.sim;
  if (tools_.size() < sim.tool_count()) tools_.resize(sim.tool_count());
  for (std::size_t t = 0; t < sim.tool_count(); ++t) {
    Tool& k = tools_[t];
    k.name = sim.rod(t).spec().name;
    const double f = sim.hand_force_mN(t);
    if (std::abs(f) > k.peak_mN) k.peak_mN = std::abs(f), k.peak_us = v.time_us;
    if (std::abs(f) > box_.full_scale_mN) ++k.over_full_scale;
    if (k.seen) {
      const double change = std::abs(f - k.last_mN);
      if (change > k.largest_change_mN) k.largest_change_mN = change, k.change_us = v.time_us;
      if (change > slew_per_tick_mN()) ++k.over_slew;
    }
    k.last_mN = f;
    k.seen = true;
  }
}

std::string ToolForces::format() const {
  std::string out;
  for (const Tool& k : tools_) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "%-16s peak %8.1f mN at %8.3f s; largest change %7.1f mN/tick at %8.3f s; %lld ticks over %.0f mN/tick, "
                  "%lld over %.0f mN\n",
                  k.name.c_str(), k.peak_mN, 1e-6 * static_cast<double>(k.peak_us), k.largest_change_mN,
                  1e-6 * static_cast<double>(k.change_us), static_cast<long long>(k.over_slew), slew_per_tick_mN(),
                  static_cast<long long>(k.over_full_scale), box_.full_scale_mN);
    out += line;
  }
  return out;
}

}  // namespace cathbox::session

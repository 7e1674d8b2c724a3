#include "session/contact_readings.hpp"

#include <algorithm>

namespace cathbox::session {

void ContactReadings::update(const tool::Simulator& sim, const tool::Snapshot& snap) {
  // The snapshot lists the case's tools, then the released coils (which keep touching the wall).
  const std::size_t tools = sim.tool_count();
  const std::size_t n = std::min(snap.tools.size(), tools + sim.detached_count());
  if (readings_.size() < n) {
    readings_.resize(n);
    held_ticks_.resize(n, 0);
    solved_ticks_.resize(n, 0);
  }
  for (std::size_t t = 0; t < n; ++t) {
    const tool::Rod& rod = t < tools ? sim.rod(t) : sim.released_view(t - tools);  // as the snapshot reads it
    const bool solved = rod.first_free_node() < rod.node_total();
    if (solved) ++solved_ticks_[t];
    if (!rod.converged() && solved) {
      ++held_ticks_[t];
      continue;
    }
    Reading r;
    const std::size_t nodes = rod.node_total();
    for (const tool::RodContact& k : snap.tools[t].contacts) {
      r.wall_mN = std::max(r.wall_mN, k.normal_force_mN);
      // The distal few nodes: the rod's node numbering ends at the tip.
      if (k.node + kTipNodes >= nodes) {
        r.tip_in_contact = true;
        r.tip_mN = std::max(r.tip_mN, k.normal_force_mN);
      }
    }
    readings_[t] = r;
  }
}

double ContactReadings::wall_mN() const {
  double m = 0.0;
  for (const Reading& r : readings_) m = std::max(m, r.wall_mN);
  return m;
}

}  // namespace cathbox::session

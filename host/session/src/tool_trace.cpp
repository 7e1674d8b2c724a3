// Every tool's state tick by tick over a window (tool_trace.hpp).
#include "session/tool_trace.hpp"

#include <glm/geometric.hpp>

namespace cathbox::session {

void ToolTrace::observe(const TickView& v) {
  const tool::Simulator& sim = v.sim;
  const std::size_t n = sim.tool_count();
  const bool first = last_mN_.size() != n;
  if (first) last_mN_.assign(n, 0.0);
  const bool inside = v.time_us >= from_us_ && v.time_us <= to_us_;
  for (std::size_t t = 0; t < n; ++t) {
    const double f = sim.hand_force_mN(t);
    if (inside) {
      const tool::Rod& rod = sim.rod(t);
      const glm::dvec3 tip = rod.tip().position_mm;
      const glm::dvec3 push = sim.tip_push_mN(t);
      std::fprintf(out_,
                   "%9.3f %-16s %s ins %8.3f F %8.1f dF %+7.1f own %8.1f clamp_shift %.3f free_from %zu of %zu converged %d its %d parts %d"
                   " | tip %.4f %.4f %.4f push %.1f %.1f %.1f | wall",
                   1e-6 * static_cast<double>(v.time_us), rod.spec().name.c_str(), t == v.input.held ? "held" : "    ",
                   sim.insertion_mm(t), f, first ? 0.0 : f - last_mN_[t], rod.hand_force_mN(), rod.clamp_shift_mm(),
                   rod.first_free_node(), rod.node_total(), rod.converged() ? 1 : 0, rod.last_iterations(), rod.last_substeps(), tip.x, tip.y, tip.z, push.x,
                   push.y, push.z);
      for (const tool::RodContact& c : rod.contacts()) {
        std::fprintf(out_, " n%u %.1f (%.2f %.2f %.2f) fr %.1f", c.node, c.normal_force_mN, c.normal.x, c.normal.y,
                     c.normal.z, glm::length(c.friction_mN));
      }
      std::fprintf(out_, " | rods");
      for (const tool::EdgeContact& c : rod.edge_contacts()) std::fprintf(out_, " e%u@%.2f %.1f", c.edge, c.s, c.force_mN);
      std::fprintf(out_, "\n");
      ++lines_;
    }
    last_mN_[t] = f;
  }
}

}  // namespace cathbox::session

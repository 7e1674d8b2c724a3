// The rod tests' shared set-up: a uniform tool, static solver settings, and an insertion in
// bounded steps.
#pragma once

#include <algorithm>
#include <cmath>

#include "tool/rod.hpp"
#include "tool/rod_contact_field.hpp"

namespace cathbox::tool::testing {

// A rod's free edges as a rod-contact field's member: a coil, or a capsule of radius_mm (> 0: an
// inflated balloon's working length).
inline RodContactField::Member member_of(const Rod& rod, bool coil, double radius_mm) {
  RodContactField::Member m;
  m.rod = &rod;
  m.edge_first = rod.first_edge();
  m.edge_last = rod.node_total() - 1;
  m.coil = coil;
  m.radius_mm = radius_mm;
  return m;
}

inline ToolSpec uniform_tool(double length, double od, double ei, double gj, double spacing, double mu) {
  ToolSpec spec;
  spec.name = "rod";
  spec.sections.push_back(ToolSection{length, od, ei, gj, 0.0});
  spec.friction = mu;
  spec.max_spacing_mm = spacing;
  spec.tip_spacing_mm = spacing;
  spec.drag_mN_s_per_mm2 = 0.0;
  return spec;
}

// Solver settings for a quasi-static check: no buckling seed, a drag floor far under the forces
// measured, and the given Newton cap and tolerance.
inline RodSettings quasi_static_settings(int newton_iterations, double convergence_mm, double min_drag) {
  RodSettings s;
  s.newton_iterations = newton_iterations;
  s.convergence_mm = convergence_mm;
  s.min_drag_mN_s_per_mm2 = min_drag;
  s.buckling_seed_mm = 0.0;
  return s;
}

inline RodSettings static_settings() {
  RodSettings s = quasi_static_settings(30, 1e-8, 1e-6);
  s.twist_iterations = 4;
  return s;
}

// Inserts to `target` in steps of at most `speed` mm per step.
inline void insert_to(Rod& rod, const WallModel& wall, double target, double per_step, double rotation = 0.0) {
  double ins = rod.insertion_mm();
  while (std::abs(target - ins) > 1e-12) {
    ins += std::clamp(target - ins, -per_step, per_step);
    rod.set_boundary(ins, rotation);
    rod.step(1e-3, wall);
  }
}

}  // namespace cathbox::tool::testing

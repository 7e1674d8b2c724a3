// The rod tests' shared set-up: a uniform tool, static solver settings, and an insertion in
// bounded steps.
#pragma once

#include <algorithm>
#include <cmath>

#include "tool/rod.hpp"

namespace cathbox::tool::testing {

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

inline RodSettings static_settings() {
  RodSettings s;
  s.newton_iterations = 30;
  s.convergence_mm = 1e-8;
  s.twist_iterations = 4;
  s.min_drag_mN_s_per_mm2 = 1e-6;
  s.buckling_seed_mm = 0.0;
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

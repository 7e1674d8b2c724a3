#pragma once
// Nested tools for the lumen-friction tests (nested_tools_test.cpp, published_friction_test.cpp):
// a catheter and a wire with no wall friction, drag or valve friction (the lumens' friction
// alone), a tightly converged solver, and an insertion in bounded steps.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "rod_test_support.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool::testing {

inline ToolSpec catheter(const std::string& name, double od, double id, double ei, double mu_lumen) {
  ToolSpec s;
  s.name = name;
  s.kind = ToolKind::kCatheter;
  s.sections = {ToolSection{600.0, od, ei, 0.8 * ei, 0.0}};
  s.inner_diameter_mm = id;
  s.lumen_friction = mu_lumen;
  s.friction = 0.0;
  s.drag_mN_s_per_mm2 = 0.0;
  s.valve_friction_mN = 0.0;  // the lumens' friction alone
  s.max_spacing_mm = 0.5;
  return s;
}

inline ToolSpec wire(const std::string& name, double od, double ei) {
  ToolSpec s;
  s.name = name;
  s.sections = {ToolSection{700.0, od, ei, 0.75 * ei, 0.0}};
  s.friction = 0.0;
  s.drag_mN_s_per_mm2 = 0.0;
  s.valve_friction_mN = 0.0;  // the lumens' friction alone
  s.max_spacing_mm = 0.5;
  return s;
}

inline RodSettings precise() { return quasi_static_settings(20, 1e-7, 1e-5); }

// Inserts `tool` to `target` in steps of at most `per_step` mm, one simulator step each.
inline void drive(Simulator& sim, std::size_t tool, double target, double per_step) {
  while (std::abs(sim.insertion_mm(tool) - target) > 1e-9) {
    const double d = std::clamp(target - sim.insertion_mm(tool), -per_step, per_step);
    sim.set_insertion(tool, sim.insertion_mm(tool) + d);
    sim.step();
  }
}

}  // namespace cathbox::tool::testing

#pragma once
// Nested tools for the lumen-friction tests (nested_tools_test.cpp, published_friction_test.cpp):
// a catheter and a wire with no wall friction, drag or valve friction (the lumens' friction
// alone), a tightly converged solver, and an insertion in bounded steps; the triaxial stack
// steered into a Y (nested_tools_test.cpp, steered_wire_test.cpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

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

// Guide > microcatheter (45 degree tip) > microwire (50 degree tip), for the Y of
// testing::y_bifurcation(2.0, 1.6, 14.0, 40.0).
inline std::vector<ToolSpec> triaxial_stack() {
  ToolSpec guide = catheter("guide", 1.6, 1.2, 20.0, 0.05);
  ToolSpec micro = catheter("micro", 0.8, 0.45, 2.0, 0.05);
  micro.inside = "guide";
  micro.sections.push_back(ToolSection{6.0, 0.8, 0.3, 0.25, 45.0});
  ToolSpec mw = wire("microwire", 0.36, 0.3);
  mw.inside = "micro";
  mw.sections.push_back(ToolSection{5.0, 0.36, 0.05, 0.04, 50.0});
  return {guide, micro, mw};
}
// 1 mm inside the start of testing::y_bifurcation's parent tube (z = -45 to 0). The stack used
// to enter at z = -58, 11 mm below the tube's closed end, and was pushed through the wall
// (10^5-10^8 mN at the hands); the depths below keep the tips where they were.
inline const Entry kTriaxialEntry{{0, 0, -44}, {0, 0, 1}};

// The stack in, then the wire alone turned half a turn (its tip into the left branch) and
// pushed 30 mm on, past the bifurcation.
inline void steer_wire_into_a_branch(Simulator& sim, double turns = 0.5, double wire_mm = 71.0) {
  drive(sim, 0, 16.0, 0.3);
  drive(sim, 1, 31.0, 0.3);
  drive(sim, 2, 41.0, 0.3);
  for (int i = 0; i < 600; ++i) {
    sim.set_rotation(2, 2.0 * M_PI * turns * i / 600.0);
    sim.step();
  }
  drive(sim, 2, wire_mm, 0.2);
}

}  // namespace cathbox::tool::testing

#pragma once
// The catheter-and-wire workload of bench_tool's step benchmarks and bench_wasm: a catheter
// (150 inserted nodes) and a guidewire (200), 1 mm node spacing, straight tips, navigated in at
// 50 mm/s while spinning slowly, then held by a hand that pushes and pulls 1 mm and twists a
// little. One definition, so the native and WebAssembly figures time the same work.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "scenario/case_file.hpp"  // the default tools
#include "tool/simulator.hpp"

namespace cathbox::bench {

struct RodNavigation {
  std::vector<tool::ToolSpec> tools;  // catheter, wire
  double cath_target_mm = 0.0;
  double wire_target_mm = 0.0;
  double rot0_rad = 0.0;
  double rot1_rad = 0.0;

  // coaxial: the wire runs inside the catheter.
  explicit RodNavigation(bool coaxial) {
    tool::ToolSpec cath = tool::default_catheter();
    cath.inner_diameter_mm = 0.6;
    cath.sections[0].outer_diameter_mm = cath.sections[1].outer_diameter_mm = cath.sections[2].outer_diameter_mm = 1.0;
    cath.sections.back().curve_deg = 0.0;
    tool::ToolSpec wire = tool::default_guidewire();
    wire.name = "wire";
    // 1 mm node spacing: 150 and 200 inserted nodes fit in the aortic path of the neuro case.
    cath.max_spacing_mm = wire.max_spacing_mm = 1.0;
    // Advanced blindly (no steering), an angled tip digs into the wall at the first sharp bend
    // and the tool jams, as a real one does; the benchmark navigates with straight tips.
    wire.sections.back().curve_deg = 0.0;
    if (coaxial) wire.inside = "catheter";
    cath_target_mm = insertion_for_nodes(cath, 150);
    wire_target_mm = insertion_for_nodes(wire, 200);
    tools = {cath, wire};
  }

  static double insertion_for_nodes(const tool::ToolSpec& spec, std::size_t nodes) {
    const tool::Rod rod(spec);
    const std::size_t n = rod.node_total();
    return rod.node_from_tip_mm(n - 1 - std::min(nodes, n - 3)) + 0.01;
  }

  // Navigate in: catheter first, then the wire; keeps the rotations reached.
  void navigate_in(tool::Simulator& sim) {
    for (std::size_t t = 0; t < 2; ++t) {
      const double target = t == 0 ? cath_target_mm : wire_target_mm;
      for (double s = 0.0; s < target; s += 0.05) {
        sim.set_insertion(t, std::min(s + 0.05, target));
        sim.set_rotation(t, s * 0.2);
        sim.step();
      }
    }
    rot0_rad = sim.rotation_rad(0);
    rot1_rad = sim.rotation_rad(1);
  }

  // The hand's input for held step i (before sim.step()).
  void hold(tool::Simulator& sim, std::uint64_t i) const {
    const double phase = static_cast<double>(i) * 1e-3;
    sim.set_insertion(1, wire_target_mm + std::sin(phase * 2.0 * M_PI) * 1.0);
    sim.set_rotation(1, rot1_rad + std::sin(phase * 3.0) * 0.5);
    sim.set_rotation(0, rot0_rad);
    sim.set_insertion(0, cath_target_mm + std::sin(phase * 1.3) * 0.5);
  }
};

}  // namespace cathbox::bench

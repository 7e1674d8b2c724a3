// bench_tool's triaxial stack (guide > microcatheter > microwire) up the neuro path, and the wall
// probes of its steps replayed on the neuro wall alone (fused or not).
#include "tool_benchmarks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "../bench_samples.hpp"
#include "../rod_navigation.hpp"
#include "bench_world.hpp"
#include "collision/obb_tree.hpp"
#include "counting_wall.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "step_times.hpp"
#include "tool/mesh_wall.hpp"
#include "tool/simulator.hpp"

namespace cathbox::bench {

using namespace cathbox::tool;

namespace {

// The triaxial stack: guide catheter > microcatheter > microwire, straight tips, 1 mm spacing.
std::vector<ToolSpec> triaxial_tools() {
  ToolSpec guide = default_catheter();
  guide.name = "guide";
  for (ToolSection& sec : guide.sections) sec.outer_diameter_mm = 2.0, sec.curve_deg = 0.0;
  guide.inner_diameter_mm = 1.2;
  ToolSpec micro = default_catheter();
  micro.name = "micro";
  for (ToolSection& sec : micro.sections) sec.outer_diameter_mm = 0.8, sec.curve_deg = 0.0;
  micro.sections[0].bending_stiffness_Nmm2 = 10.0;
  micro.inner_diameter_mm = 0.45;
  micro.inside = "guide";
  micro.sections[0].length_mm += 400.0;
  ToolSpec wire = default_guidewire();
  wire.name = "wire";
  wire.sections.back().curve_deg = 0.0;
  wire.inside = "micro";
  guide.max_spacing_mm = micro.max_spacing_mm = wire.max_spacing_mm = 1.0;
  return {guide, micro, wire};
}

struct TriaxialTargets {
  double insertion[3];
};

// Inserts the stack to 150 / 200 / 200 nodes, each tool spinning slowly on its way in.
TriaxialTargets insert_triaxial(Simulator& sim, const std::vector<ToolSpec>& tools) {
  const TriaxialTargets targets{{RodNavigation::insertion_for_nodes(tools[0], 150), RodNavigation::insertion_for_nodes(tools[1], 200),
                                 RodNavigation::insertion_for_nodes(tools[2], 200)}};
  for (std::size_t t = 0; t < 3; ++t) {
    for (double s = t == 0 ? 0.0 : targets.insertion[t - 1] - 5.0; s < targets.insertion[t]; s += 0.05) {
      sim.set_insertion(t, std::min(s + 0.05, targets.insertion[t]));
      sim.set_rotation(t, s * 0.2);
      sim.step();
    }
  }
  return targets;
}

// The hand at step i: the coaxial bench's push-pull and twist on the wire, the microcatheter
// breathing.
void drive_triaxial(Simulator& sim, const TriaxialTargets& targets, std::uint64_t i) {
  const double phase = static_cast<double>(i) * 1e-3;
  sim.set_insertion(2, targets.insertion[2] + std::sin(phase * 2.0 * M_PI) * 1.0);
  sim.set_rotation(2, targets.insertion[2] * 0.2 + std::sin(phase * 3.0) * 0.5);
  sim.set_insertion(1, targets.insertion[1] + std::sin(phase * 1.3) * 0.5);
}


// The wall probes of the triaxial bench's steps, replayed on the neuro wall alone: 5000 steps
// of BM_StepTriaxial's motion are recorded once (every probe's node, centre and radii), then
// replayed on a fresh MeshWall (fresh hints), with fused probes (fused:1, the default: a node
// that touched the wall gets one sphere query giving its contacts and closest point) or
// without (fused:0: closest point, then sphere query). Per replayed step the thread CPU time of its
// probes: median and p99 over the steps (`step_median_us`, `step_p99_us`), the mean per probe
// and the probes of the tail steps: what the wall costs the triaxial step, without the solver.
struct ProbeReplay {
  std::vector<ProbeRecord> records;
  std::size_t nodes = 0;
  std::uint32_t steps = 0;
  std::optional<cathbox::vessel::SurfaceMesh> mesh;
};

const ProbeReplay& triaxial_probes() {
  static const ProbeReplay replay = [] {
    ProbeReplay r;
    const CaseParse c = load_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.case");
    if (!c) return r;
    WorldBuild built = build_world(*c);
    if (!built || (*built)->mesh() == nullptr) return r;
    r.mesh = *(*built)->mesh();
    const std::vector<ToolSpec> tools = triaxial_tools();
    CountingWall wall((*built)->wall());
    Simulator sim(wall, tools, (*built)->entry());
    const TriaxialTargets targets = insert_triaxial(sim, tools);
    wall.record(&r.records);
    for (std::uint64_t i = 0; i < 5000; ++i) {
      drive_triaxial(sim, targets, i);
      sim.step();
      wall.next_step();
    }
    wall.record(nullptr);
    r.nodes = wall.nodes();
    r.steps = 5000;
    const std::uint32_t first_step = r.records.front().step;
    for (ProbeRecord& p : r.records) p.step -= first_step;
    return r;
  }();
  return replay;
}

}  // namespace

// Guide (150 inserted nodes) > microcatheter (200) > microwire (200) up the neuro path, then
// the coaxial bench's push-pull and twist on the wire with the microcatheter breathing.
void BM_StepTriaxial(benchmark::State& state) {
  static World world = make_world();
  const std::vector<ToolSpec> tools = triaxial_tools();
  const CountingWall wall(*world.wall);
  Simulator sim(wall, tools, world.entry);
  const TriaxialTargets targets = insert_triaxial(sim, tools);
  StepTimes times(1 << 16);
  times.count_probes(wall);
  std::uint64_t i = 0;
  double iterations = 0.0;
  std::uint64_t capped = 0;  // steps where a rod used every Newton iteration it may
  std::size_t solved = 0;
  for (auto _ : state) {
    drive_triaxial(sim, targets, i++);
    times.step(sim);
    bool hit_cap = false;
    for (std::size_t t = 0; t < 3; ++t) {
      iterations += sim.rod(t).last_iterations();
      hit_cap = hit_cap || sim.rod(t).last_iterations() >= RodSettings{}.newton_iterations;
    }
    if (hit_cap) ++capped;
  }
  for (std::size_t t = 0; t < 3; ++t) solved += sim.rod(t).node_total() - sim.rod(t).first_free_node();
  times.report_tail(state, {"guide", "micro", "wire"});
  times.report(state);
  state.counters["newton_its"] = iterations / static_cast<double>(std::max<std::uint64_t>(1, i));
  state.counters["capped_pct"] = 100.0 * static_cast<double>(capped) / static_cast<double>(std::max<std::uint64_t>(1, i));
  state.counters["solved_nodes"] = static_cast<double>(solved);
  state.counters["wire_depth_mm"] = sim.tip_depth_mm(2);
  state.SetLabel(world.name);
}

void BM_WallReprobe(benchmark::State& state) {
  const ProbeReplay& replay = triaxial_probes();
  if (!replay.mesh || replay.records.empty()) {
    state.SkipWithError("the neuro case did not load");
    return;
  }
  cathbox::collision::TreeBuild tree = cathbox::collision::ObbTree::build(*replay.mesh);
  if (!tree) {
    state.SkipWithError(tree.error().message.c_str());
    return;
  }
  MeshWall wall(std::move(*tree));
  wall.set_fused_probes(state.range(0) != 0);
  std::vector<WallHint> hints(replay.nodes);
  std::vector<double> step_us;
  std::vector<std::size_t> step_probes;
  step_us.reserve(replay.steps * 8);
  WallContact out;
  for (auto _ : state) {
    // Fresh hints each pass: every node takes a slot again (reset with its touching flag).
    std::fill(hints.begin(), hints.end(), WallHint{});
    std::size_t k = 0;
    while (k < replay.records.size()) {
      const std::uint32_t step = replay.records[k].step;
      const std::size_t first = k;
      const double t0 = thread_cpu_us();
      for (; k < replay.records.size() && replay.records[k].step == step; ++k) {
        const ProbeRecord& r = replay.records[k];
        benchmark::DoNotOptimize(wall.probe(r.probe, hints[r.node], out));
      }
      step_us.push_back(thread_cpu_us() - t0);
      step_probes.push_back(k - first);
    }
  }
  std::vector<double> sorted = step_us;
  const double p99 = StepTimes::pick(sorted, 0.99);
  double tail_probes = 0.0, tail_steps = 0.0, total_us = 0.0, total_probes = 0.0;
  for (std::size_t i = 0; i < step_us.size(); ++i) {
    total_us += step_us[i];
    total_probes += static_cast<double>(step_probes[i]);
    if (step_us[i] >= p99) tail_probes += static_cast<double>(step_probes[i]), tail_steps += 1.0;
  }
  state.counters["step_median_us"] = StepTimes::pick(sorted, 0.5);
  state.counters["step_p99_us"] = p99;
  state.counters["ns_per_probe"] = 1e3 * total_us / std::max(1.0, total_probes);
  state.counters["probes_per_step"] = total_probes / static_cast<double>(std::max<std::size_t>(1, step_us.size()));
  state.counters["tail_probes"] = tail_probes / std::max(1.0, tail_steps);
  state.SetLabel(state.range(0) != 0 ? "fused probes" : "closest point, then sphere");
}

}  // namespace cathbox::bench

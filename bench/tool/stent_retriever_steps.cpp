// bench_tool's stent retriever: across a clot in an analytic artery, and the bundled M1 case
// driven by its own script (dwell, then retrieval).
#include "tool_benchmarks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "counting_wall.hpp"
#include "scenario/action_script.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "scenario/script_player.hpp"
#include "step_times.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::bench {

using namespace cathbox::tool;

// The stent retriever: unsheathing, then retrieval with its clot (header comment).
void BM_StepStentRetriever(benchmark::State& state) {
  // 40 mm straight along +z, a 90 degree bend of 6 mm radius towards +x, 60 mm straight.
  std::vector<glm::dvec3> axis{{0, 0, -10.0}};
  for (int k = 0; k <= 90; ++k) {
    const double a = 0.5 * M_PI * k / 90.0;
    axis.push_back({6.0 - 6.0 * std::cos(a), 0, 40.0 + 6.0 * std::sin(a)});
  }
  axis.push_back(axis.back() + glm::dvec3(60.0, 0, 0));
  TubeNetworkWall wall;
  wall.add_polyline(axis, 1.4, 0);
  wall.build();
  ToolSpec micro = default_microcatheter();
  micro.inner_diameter_mm = 0.53;
  ToolSpec stent;
  stent.name = "stent";
  stent.sections = {ToolSection{1700.0, 0.4, 30.0, 23.0, 0.0}, ToolSection{60.0, 0.4, 5.0, 4.0, 0.0}, ToolSection{20.0, 0.45, 2.0, 1.5, 0.0}};
  stent.friction = 0.08;
  stent.inside = micro.name;
  stent.stent.diameter_mm = 4.0;
  stent.stent.length_mm = 20.0;
  const std::vector<ToolSpec> tools{micro, stent};
  Simulator sim(wall, tools, Entry{{0, 0, -5.0}, {0, 0, 1}});
  const double depth = 40.0 + 6.0 * 0.5 * M_PI + 40.0;
  for (double x = 0.0; x < depth; x += 0.04) {
    sim.set_insertion(0, x + 1.0);
    sim.set_insertion(1, x);
    sim.step();
  }
  StepTimes times(1 << 14);
  std::uint64_t i = 0;
  double micro_at = sim.insertion_mm(0), stent_at = sim.insertion_mm(1), rf_N = 0.0, peak_mN = 0.0;
  for (auto _ : state) {
    if (i < 5000) {
      micro_at -= 0.005;
      sim.set_insertion(0, micro_at);
    } else {
      if (i == 5000) {
        rf_N = sim.stent(1)->state().radial_force_N;
        sim.set_stent_payload(1, 78.0);
      }
      stent_at -= 0.01;
      sim.set_insertion(1, stent_at);
    }
    ++i;
    times.step(sim);
    peak_mN = std::max(peak_mN, -sim.hand_force_mN(1));
  }
  times.report(state);
  state.counters["radial_force_N"] = rf_N;
  state.counters["peak_pull_N"] = 1e-3 * peak_mN;
  state.SetLabel("stent retriever across a clot, 2.8 mm artery");
}

// The bundled case (cases/neuro_thrombectomy_m1_stentretriever.case, the neuro mesh through the
// collision tree: balloon guide > microcatheter > microwire, then the 4 x 20 mm stent on its push
// wire) driven by its own action script (the simulator alone, no session): the access and the
// unsheathing across the M1 clot are played untimed (48 s of the script); then timed: 2000 steps
// of the dwell (the stent expanded, nothing moving), and from the script's 228 s the
// microcatheter drawn into the guide at 20 mm/s and the stent pulled back at 10 mm/s with its
// integrated clot's 78 mN payload, to 240 s (12,000 steps).
void BM_StepStentRetrieverCase(benchmark::State& state) {
  const std::string stem = std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_thrombectomy_m1_stentretriever";
  const CaseParse c = load_case(stem + ".case");
  const ScriptParse script = load_script(stem + ".actions");
  if (!c || !script) {
    state.SkipWithError("neuro_thrombectomy_m1_stentretriever: the case or its script did not load");
    return;
  }
  WorldBuild built = build_world(*c);
  if (!built) {
    state.SkipWithError("neuro_thrombectomy_m1_stentretriever: no world");
    return;
  }
  CountingWall wall((*built)->wall());
  Simulator sim(wall, c->tools, (*built)->entry());
  std::vector<ScriptPlayer::ToolInfo> infos;
  for (std::size_t t = 0; t < sim.tool_count(); ++t) infos.push_back(tool_info(sim.rod(t).spec()));
  cathbox::base::Result<ScriptPlayer> player = ScriptPlayer::make(*script, infos, sim.active_tool(), "script");
  const std::size_t stent = sim.tool_count() - 1;
  if (!player || !sim.stent(stent)) {
    state.SkipWithError("the script does not fit the case, or its last tool is no stent retriever");
    return;
  }
  auto play = [&](std::int64_t now) {
    const ScriptPlayer::Step step = player->advance(now);
    if (step.selected) sim.select(*step.selected);
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      sim.set_insertion(t, player->insertion_mm(t));
      sim.set_rotation(t, player->rotation_rad(t));
    }
  };
  constexpr std::int64_t kDeployed_ms = 48000, kDwellSteps = 2000, kRetrieve_ms = 228000, kPull_ms = 234000;
  std::int64_t now = 0;
  for (; now < kDeployed_ms; ++now) {
    play(now);
    sim.step(1e-3);
  }
  const double rf_N = sim.stent(stent)->state().radial_force_N;
  const double unsheathed_mm = sim.stent(stent)->state().unsheathed_mm;
  StepTimes dwell(kDwellSteps), retrieval(1 << 14);
  dwell.count_probes(wall);
  retrieval.count_probes(wall);
  std::int64_t i = 0, peak_ms = 0;
  double peak_mN = 0.0;
  for (auto _ : state) {
    if (i == kDwellSteps) {  // the rest of the dwell: nothing moves
      for (; now < kRetrieve_ms; ++now) player->advance(now);
      retrieval.count_probes(wall);
    }
    if (now == kPull_ms) sim.set_stent_payload(stent, 78.0);
    play(now++);
    (i++ < kDwellSteps ? dwell : retrieval).step(sim);
    if (now > kPull_ms && sim.rod(stent).converged() && -sim.hand_force_mN(stent) > peak_mN) {
      peak_mN = -sim.hand_force_mN(stent);
      peak_ms = now;
    }
  }
  state.counters["peak_pull_at_ms"] = static_cast<double>(peak_ms);
  const std::vector<std::string> names{"guide", "micro", "wire", "stent"};
  dwell.report_tail(state, names, "dwell_");
  retrieval.report_tail(state, names, "retrieval_");
  dwell.report(state, "dwell_");
  retrieval.report(state, "retrieval_");
  StepTimes all(1 << 15);
  all.add(dwell);
  all.add(retrieval);
  all.report(state);
  state.counters["radial_force_N"] = rf_N;
  state.counters["unsheathed_mm"] = unsheathed_mm;
  state.counters["peak_pull_N"] = 1e-3 * peak_mN;
  state.SetLabel("bundled M1 case: dwell, then retrieval");
}

}  // namespace cathbox::bench

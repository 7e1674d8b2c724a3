// bench_tool's catheter and wire: the coaxial and separate step benchmarks (RodNavigation's
// workload) and host/python's DualDevice-v0 under random actions at a 6 ms tick.
#include "tool_benchmarks.hpp"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include "../bench_samples.hpp"
#include "../rod_navigation.hpp"
#include "bench_world.hpp"
#include "scenario/case_file.hpp"
#include "step_times.hpp"
#include "tool/simulator.hpp"

namespace cathbox::bench {

using namespace cathbox::tool;

namespace {

void run(benchmark::State& state, bool coaxial) {
  static World world = make_world();
  RodNavigation nav(coaxial);
  Simulator sim(*world.wall, nav.tools, world.entry);
  nav.navigate_in(sim);
  StepTimes times(1 << 16);
  std::vector<double> converged_samples;
  double iterations = 0.0;
  double its0 = 0.0;
  std::uint64_t i = 0;
  std::size_t contacts = 0;
  std::uint64_t capped = 0;  // steps where a rod used every Newton iteration it may
  const int cap = RodSettings{}.newton_iterations;
  std::uint64_t capped_rod[2] = {0, 0};
  for (auto _ : state) {
    // A hand that pushes and pulls 1 mm and twists a little, as during navigation.
    nav.hold(sim, i++);
    times.step(sim);
    iterations += sim.rod(0).last_iterations() + sim.rod(1).last_iterations();
    if (sim.rod(0).last_iterations() >= cap || sim.rod(1).last_iterations() >= cap) {
      ++capped;
    } else {
      converged_samples.push_back(times.last_wall_us());
    }
    its0 += sim.rod(0).last_iterations();
    if (sim.rod(0).last_iterations() >= cap) ++capped_rod[0];
    if (sim.rod(1).last_iterations() >= cap) ++capped_rod[1];
    contacts += sim.rod(0).contacts().size() + sim.rod(1).contacts().size();
  }
  const auto solved = [&](std::size_t t) { return sim.rod(t).node_total() - sim.rod(t).first_free_node(); };
  std::size_t wire_inserted = 0;
  for (std::size_t k = 0; k < sim.rod(1).node_total(); ++k) {
    if (sim.insertion_mm(1) - sim.rod(1).node_from_tip_mm(k) > 0.0) ++wire_inserted;
  }
  times.report_tail(state, {"cath", "wire"});
  times.report(state);
  // Where the tail comes from: the steps in which a rod ran out of Newton iterations.
  state.counters["capped_pct"] = 100.0 * static_cast<double>(capped) / static_cast<double>(std::max<std::uint64_t>(1, i));
  if (!converged_samples.empty()) state.counters["p99_converged_us"] = StepTimes::pick(converged_samples, 0.99);
  state.counters["cath_capped_pct"] = 100.0 * static_cast<double>(capped_rod[0]) / static_cast<double>(std::max<std::uint64_t>(1, i));
  state.counters["cath_its"] = its0 / static_cast<double>(std::max<std::uint64_t>(1, i));
  state.counters["newton_its"] = iterations / static_cast<double>(std::max<std::uint64_t>(1, i));
  state.counters["cath_nodes"] = static_cast<double>(solved(0));
  state.counters["wire_nodes_in"] = static_cast<double>(wire_inserted);
  state.counters["solved_nodes"] = static_cast<double>(solved(0) + solved(1));
  state.counters["wire_tip_depth_mm"] = glm::dot(sim.tip(1).position_mm - world.entry.point_mm, world.entry.direction);
  state.counters["wire_force_mN"] = sim.hand_force_mN(1);
  state.counters["contacts"] = static_cast<double>(contacts) / static_cast<double>(std::max<std::uint64_t>(1, i));
  state.SetLabel(world.name);
}

}  // namespace

// host/python's DualDevice-v0 under a random policy at stEVE's physics step (period_us=6000):
// the neuro case's catheter with its guidewire inside, one env step = 22 ticks of 6 ms (1/7.5 s),
// each device's speeds drawn every env step uniformly in stEVE's box (±50 mm/s, ±3.14 rad/s) from
// a fixed seed, insertions clamped to [0, max]; episodes of 75 env steps (10 s, as
// bench/python/bench_env.py) from a new simulator. Thread CPU time per env step: its median
// against stEVE's 125-250 ms (4-8 steps/s per worker, derived from its published training).
// The simulator alone on its own random sequence (10 episodes): a figure to compare builds of the
// rod and the wall probe by, not the env's (bench_env.py's 75 steps from seed 0 spend ~1.5 ms
// per step in Session.step where this spends ~0.85 ms: another sequence, and the session's tick).
void BM_DualDeviceRandom6ms(benchmark::State& state) {
  const CaseParse c = load_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.case");
  if (!c || c->tools.size() != 2) {
    state.SkipWithError("neuro.case: no catheter and guidewire");
    return;
  }
  static World world = make_world();
  constexpr int kTicks = 22;
  constexpr int kEpisodeSteps = 75;
  std::vector<double> cpu_us;
  std::unique_ptr<Simulator> sim;
  std::mt19937_64 rng(0);
  std::uniform_real_distribution<double> speed(-50.0, 50.0), spin(-3.14, 3.14);
  double insertion[2] = {0.0, 0.0}, rotation[2] = {0.0, 0.0};
  int step = 0;
  std::uint64_t ticks = 0, unconverged = 0;
  for (auto _ : state) {
    if (step % kEpisodeSteps == 0) {
      state.PauseTiming();
      sim = std::make_unique<Simulator>(*world.wall, c->tools, world.entry);
      insertion[0] = insertion[1] = rotation[0] = rotation[1] = 0.0;
      state.ResumeTiming();
    }
    ++step;
    double v[2], w[2];
    for (int t = 0; t < 2; ++t) v[t] = speed(rng), w[t] = spin(rng);
    const double c0 = thread_cpu_us();
    for (int k = 0; k < kTicks; ++k) {
      for (std::size_t t = 0; t < 2; ++t) {
        insertion[t] = std::clamp(insertion[t] + v[t] * 0.006, 0.0, sim->max_insertion_mm(t));
        rotation[t] += w[t] * 0.006;
        sim->set_insertion(t, insertion[t]);
        sim->set_rotation(t, rotation[t]);
      }
      sim->step(0.006);
      for (std::size_t t = 0; t < 2; ++t) {
        ++ticks;
        if (sim->rod(t).first_free_node() < sim->rod(t).node_total() && !sim->rod(t).converged()) ++unconverged;
      }
    }
    cpu_us.push_back(thread_cpu_us() - c0);
  }
  double total_us = 0.0;
  for (const double us : cpu_us) total_us += us;
  std::sort(cpu_us.begin(), cpu_us.end());
  const double median = cathbox::bench::quantile_sorted(cpu_us, 0.5);
  state.counters["cpu_mean_us_per_env_step"] = total_us / static_cast<double>(std::max<std::size_t>(1, cpu_us.size()));
  state.counters["cpu_median_us_per_env_step"] = median;
  state.counters["env_steps_per_cpu_s"] = 1e6 / median;
  state.counters["x_stEVE_8_per_s"] = 1e6 / median / 8.0;
  state.counters["unconverged_rod_ticks_pct"] = 100.0 * static_cast<double>(unconverged) / static_cast<double>(std::max<std::uint64_t>(1, ticks));
  state.SetLabel(world.name);
}

void BM_StepCoaxial(benchmark::State& state) { run(state, true); }
void BM_StepSeparate(benchmark::State& state) { run(state, false); }


}  // namespace cathbox::bench

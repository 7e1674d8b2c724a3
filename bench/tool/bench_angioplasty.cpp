// Balloon angioplasty's wall swap in the bundled neuro case (cases/neuro_angioplasty.case):
//   BM_WallRebuild: the new wall of the widened lumen (re-mesh + OBB tree + MeshWall: what
//     WallSwap's builder does after each lumen change, e.g. a deflation), median and p99 in ms,
//     against the 300 ms at which the swap is due (WallSwap::kDefaultLatencyTicks); the tree
//     reuses the regions the balloon left alone from the case's wall (the session's builder,
//     cached_mesh_wall_builder). BM_WallRebuildFromScratch: the same without the cache.
//   BM_StepWhileRebuilding: the haptic step (wire and balloon catheter across the lesion) while
//     the worker rebuilds the wall on the other core, asked again after each swap (the
//     session's cached builder, alternating between the widened and the original lumen), beside
//     BM_StepNoRebuild, the same steps without it. Wall and thread-CPU medians and p99 in us.
//   BM_WallSwapWhileStepping: what the session sees: the cached builder on the worker while the
//     haptic loop runs at 1 kHz on this thread, each wall due 300 ticks after its request; how
//     many due ticks had to wait for the builder and how long; the worker's wall and CPU time
//     per build; the haptic step meanwhile.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include <time.h>

#include <benchmark/benchmark.h>

#include "tool/angioplasty.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "collision/obb_tree.hpp"
#include "vessel/vessel_mesher.hpp"
#include "../bench_samples.hpp"

namespace {

using namespace cathbox::tool;
namespace vessel = cathbox::vessel;

struct Scene {
  Case c;
  std::optional<vessel::VesselModel> source;
  std::unique_ptr<WallModel> wall;
  Entry entry;
  vessel::VesselModel widened;  // the lumen after 6 atm with the case's balloon over the lesion
};

std::optional<Scene> load_scene() {
  CaseParse c = load_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_angioplasty.case");
  if (!c) return std::nullopt;
  WorldBuild world = build_world(*c);
  if (!world || (*world)->source_model() == nullptr) return std::nullopt;
  Scene s;
  s.c = *c;
  s.source = *(*world)->source_model();
  s.entry = (*world)->entry();
  s.wall = (*world)->release_wall();
  // The case's balloon (5.0 mm at 6 atm) along the lesion's centre line, inflated and deflated.
  LumenRemodel lumen(*s.source);
  const vessel::Segment& seg = s.source->segments[lumen.lesion().segment];
  std::vector<glm::dvec3> axis;
  const std::size_t w = lumen.lesion().worst;
  for (std::size_t i = w >= 6 ? w - 6 : 0; i < std::min(seg.points.size(), w + 7); ++i) axis.push_back(seg.points[i].pos_mm);
  lumen.apply({axis, 5.0, true});
  lumen.apply({axis, 0.0, false});
  s.widened = lumen.model();
  return s;
}

using cathbox::bench::thread_cpu_us;
double pick(const std::vector<double>& v, double q) { return cathbox::bench::quantile(v, q); }

// The new wall of the widened lumen; `reuse`: with the tree cache of the wall before it (the
// case's), as the session's builder has it, else from scratch.
void wall_rebuild(benchmark::State& state, bool reuse) {
  std::optional<Scene> scene = load_scene();
  if (!scene) {
    state.SkipWithError("cases/neuro_angioplasty.case did not load");
    return;
  }
  std::vector<double> ms, cpu_ms, mesh_ms, tree_ms;
  std::size_t reused = 0, built = 0;
  for (auto _ : state) {
    state.PauseTiming();
    cathbox::collision::TreeCache cache;
    if (reuse) benchmark::DoNotOptimize(build_mesh_wall(*scene->source, &cache));  // the wall before
    state.ResumeTiming();
    const double c0 = thread_cpu_us();
    const auto t0 = std::chrono::steady_clock::now();
    auto wall = build_mesh_wall(scene->widened, reuse ? &cache : nullptr);
    const auto t1 = std::chrono::steady_clock::now();
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    cpu_ms.push_back(1e-3 * (thread_cpu_us() - c0));
    if (!wall) state.SkipWithError(wall.error().message.c_str());
    reused = cache.reused_regions();
    built = cache.built_regions();
    benchmark::DoNotOptimize(wall);
    // Its two parts: the surface, then the tree (thread CPU).
    state.PauseTiming();
    cathbox::collision::TreeCache again;
    if (reuse) benchmark::DoNotOptimize(cathbox::collision::ObbTree::build(vessel::build_vessel_surface(*scene->source).mesh, {}, again));
    state.ResumeTiming();
    const double m0 = thread_cpu_us();
    vessel::VesselSurface surface = vessel::build_vessel_surface(scene->widened);
    const double m1 = thread_cpu_us();
    auto tree = cathbox::collision::ObbTree::build(surface.mesh, {}, again);
    mesh_ms.push_back(1e-3 * (m1 - m0));
    tree_ms.push_back(1e-3 * (thread_cpu_us() - m1));
    benchmark::DoNotOptimize(tree);
  }
  state.counters["median_ms"] = pick(ms, 0.5);
  state.counters["p99_ms"] = pick(ms, 0.99);
  state.counters["cpu_median_ms"] = pick(cpu_ms, 0.5);
  state.counters["cpu_p99_ms"] = pick(cpu_ms, 0.99);
  state.counters["cpu_mesh_ms"] = pick(mesh_ms, 0.5);
  state.counters["cpu_tree_ms"] = pick(tree_ms, 0.5);
  state.counters["budget_ms"] = static_cast<double>(WallSwap::kDefaultLatencyTicks);
  if (reuse) {
    state.counters["regions_reused"] = static_cast<double>(reused);
    state.counters["regions_built"] = static_cast<double>(built);
  }
}

void BM_WallRebuild(benchmark::State& state) { wall_rebuild(state, true); }
void BM_WallRebuildFromScratch(benchmark::State& state) { wall_rebuild(state, false); }

// Wire across the lesion, balloon catheter over it (the case's script, without inflating).
void place_tools(Simulator& sim) {
  const std::size_t wire = sim.find_tool("guidewire");
  const std::size_t cath = sim.find_tool("balloon");
  for (int i = 1; i <= 5000; ++i) {
    sim.set_insertion(wire, 0.02 * i);
    sim.step();
  }
  for (int i = 1; i <= 5800; ++i) {
    sim.set_insertion(cath, 0.01 * i);
    sim.step();
  }
}

// The session's builder (cached_mesh_wall_builder) with its first wall built by it, and a
// simulator on that wall with the tools across the lesion.
struct SwapRig {
  std::optional<Scene> scene;
  std::unique_ptr<WallSwap> swap;
  std::unique_ptr<Simulator> sim;
  std::size_t wire = 0;
  double base = 0.0;
  // The lumens the rebuilds alternate between: each is a real change from the last wall, so the
  // cache reuses only the regions the balloon left alone, as after an inflation or a deflation.
  [[nodiscard]] const vessel::VesselModel& lumen(std::uint64_t k) const { return k % 2 == 0 ? scene->widened : *scene->source; }
  // One haptic tick: the wire moves back and forth by 1 mm, then the swap is polled (a due
  // wall's tick waits for the builder when it is late).
  bool tick(std::uint64_t i) {
    const double phase = static_cast<double>(i) * 1e-3;
    sim->set_insertion(wire, base + std::sin(phase * 2.0 * M_PI) * 1.0);
    sim->step();
    return swap->poll(*sim, static_cast<std::int64_t>(sim->steps()));
  }
};

std::optional<SwapRig> make_rig(benchmark::State& state) {
  SwapRig rig;
  rig.scene = load_scene();
  if (!rig.scene) {
    state.SkipWithError("cases/neuro_angioplasty.case did not load");
    return std::nullopt;
  }
  WallBuilder builder = cached_mesh_wall_builder();
  auto first = builder(*rig.scene->source);
  if (!first) {
    state.SkipWithError(first.error().message.c_str());
    return std::nullopt;
  }
  rig.swap = std::make_unique<WallSwap>(std::move(*first), std::move(builder), WallSwap::Mode::kWorker);
  rig.sim = std::make_unique<Simulator>(rig.swap->wall(), rig.scene->c.tools, rig.scene->entry);
  place_tools(*rig.sim);
  rig.wire = rig.sim->find_tool("guidewire");
  rig.base = rig.sim->insertion_mm(rig.wire);
  return rig;
}

void put_builds(benchmark::State& state, const WallSwap& swap) {
  const std::vector<double> builds = swap.build_seconds();
  const std::vector<double> cpu = swap.build_cpu_seconds();
  state.counters["build_median_ms"] = 1e3 * pick(builds, 0.5);
  state.counters["build_p99_ms"] = 1e3 * pick(builds, 0.99);
  state.counters["build_cpu_median_ms"] = 1e3 * pick(cpu, 0.5);
  state.counters["build_cpu_p99_ms"] = 1e3 * pick(cpu, 0.99);
}

// The haptic step as fast as it goes, while the worker rebuilds on the other core (the session's
// cached builder, alternating lumens; asked again after each swap), beside the same steps
// without it. The due ticks that waited for the builder are left out of the step's figures.
void step_bench(benchmark::State& state, bool rebuild) {
  std::optional<SwapRig> rig = make_rig(state);
  if (!rig) return;
  std::vector<double> wall_us, cpu_us;
  wall_us.reserve(1 << 16);
  cpu_us.reserve(1 << 16);
  std::uint64_t i = 0, during = 0, k = 0;
  for (auto _ : state) {
    if (rebuild && !rig->swap->pending()) rig->swap->request(rig->lumen(k++), static_cast<std::int64_t>(rig->sim->steps()));
    const std::uint64_t waits = rig->swap->waits();
    const double c0 = thread_cpu_us();
    const auto t0 = std::chrono::steady_clock::now();
    rig->tick(i++);
    const auto t1 = std::chrono::steady_clock::now();
    if (rig->swap->waits() != waits) continue;
    cpu_us.push_back(thread_cpu_us() - c0);
    wall_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    if (rig->swap->pending()) ++during;
  }
  rig->swap->drain();
  state.counters["median_us"] = pick(wall_us, 0.5);
  state.counters["p99_us"] = pick(wall_us, 0.99);
  state.counters["cpu_median_us"] = pick(cpu_us, 0.5);
  state.counters["cpu_p99_us"] = pick(cpu_us, 0.99);
  state.counters["steps_during_rebuild"] = static_cast<double>(during);
  state.counters["swaps"] = static_cast<double>(rig->swap->swaps());
  state.counters["waits"] = static_cast<double>(rig->swap->waits());
  if (rebuild) put_builds(state, *rig->swap);
}

void BM_StepWhileRebuilding(benchmark::State& state) { step_bench(state, true); }
void BM_StepNoRebuild(benchmark::State& state) { step_bench(state, false); }

// What the session sees: one iteration is one wall, from the request to the tick that swaps it
// in (300 ticks later, as in the session), while the haptic loop runs at 1 kHz on this thread
// (busy-waiting for the next millisecond, as a loop that owns its core). The builder is the
// session's (cached, alternating lumens). Counters: the due ticks that waited for the builder
// (waits) and how long (wait_*, ms), the worker's wall and CPU time per build (build_*), the
// haptic step on the other ticks (step_*, us).
void BM_WallSwapWhileStepping(benchmark::State& state) {
  std::optional<SwapRig> rig = make_rig(state);
  if (!rig) return;
  using Clock = std::chrono::steady_clock;
  std::vector<double> step_us, step_cpu_us;
  step_us.reserve(1 << 16);
  step_cpu_us.reserve(1 << 16);
  std::uint64_t i = 0, k = 0;
  auto next = Clock::now();
  for (auto _ : state) {
    rig->swap->request(rig->lumen(k++), static_cast<std::int64_t>(rig->sim->steps()));
    for (bool swapped = false; !swapped;) {
      next += std::chrono::microseconds(1000);
      while (Clock::now() < next) {
      }
      const double c0 = thread_cpu_us();
      const auto t0 = Clock::now();
      swapped = rig->tick(i++);
      const auto t1 = Clock::now();
      if (!swapped) {
        step_cpu_us.push_back(thread_cpu_us() - c0);
        step_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
      }
      if (t1 > next + std::chrono::microseconds(1000)) next = t1;  // late: no burst to catch up
    }
  }
  const WallSwap::WaitTally& tally = rig->swap->wait_tally();
  std::vector<double> wait_ms = tally.recent_seconds();
  for (double& w : wait_ms) w *= 1e3;
  state.counters["waits"] = static_cast<double>(tally.count);
  state.counters["wait_median_ms"] = wait_ms.empty() ? 0.0 : pick(wait_ms, 0.5);
  state.counters["wait_max_ms"] = tally.max_seconds * 1e3;
  put_builds(state, *rig->swap);
  state.counters["step_median_us"] = pick(step_us, 0.5);
  state.counters["step_p99_us"] = pick(step_us, 0.99);
  state.counters["step_cpu_median_us"] = pick(step_cpu_us, 0.5);
  state.counters["step_cpu_p99_us"] = pick(step_cpu_us, 0.99);
  state.counters["budget_ms"] = static_cast<double>(WallSwap::kDefaultLatencyTicks);
}

}  // namespace

BENCHMARK(BM_WallRebuild)->Unit(benchmark::kMillisecond)->Iterations(15);
BENCHMARK(BM_WallRebuildFromScratch)->Unit(benchmark::kMillisecond)->Iterations(15);
BENCHMARK(BM_StepNoRebuild)->Unit(benchmark::kMicrosecond)->Iterations(3000);
BENCHMARK(BM_StepWhileRebuilding)->Unit(benchmark::kMicrosecond)->Iterations(10000);
BENCHMARK(BM_WallSwapWhileStepping)->Unit(benchmark::kMillisecond)->Iterations(40);
BENCHMARK_MAIN();

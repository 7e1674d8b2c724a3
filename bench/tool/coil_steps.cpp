// bench_tool's coils: one coil deployed into a 6.4 mm sphere, and a third coil into the same
// sphere already holding 300 mm.
#include "tool_benchmarks.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "scenario/case_file.hpp"
#include "step_times.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::bench {

using namespace cathbox::tool;

// A 150 mm coil at 0.5 mm spacing pushed at 20 mm/s (0.02 mm a step) out of a microcatheter
// whose tip is 1 mm inside a 6.4 mm sphere: every step of the deployment is timed.
void BM_StepCoilDeploy(benchmark::State& state) {
  constexpr double kSphereR = 3.2, kCoilLength = 150.0;
  const glm::dvec3 centre(0.0, 0.0, 20.0);
  TubeNetworkWall wall;
  wall.add_tube(Tube{{0, 0, -5}, centre, 1.0, 1.0, 0});
  wall.add_tube(Tube{centre, centre + glm::dvec3(0, 0, 1e-3), kSphereR, kSphereR, 1});
  wall.build();
  const ToolSpec micro = default_microcatheter();
  const ToolSpec coil = default_coil(kCoilLength, 5.0);
  const std::vector<ToolSpec> tools{micro, coil};
  const Entry entry{{0, 0, -3}, {0, 0, 1}};
  Simulator sim(wall, tools, entry);
  const double micro_depth = centre.z - std::sqrt(kSphereR * kSphereR - 1.0) + 1.0 - entry.point_mm.z;
  for (double s = 0.0; s < micro_depth; s += 0.2) {
    sim.set_insertion(0, std::min(s + 0.2, micro_depth));
    sim.set_insertion(1, std::min(s + 0.2, micro_depth) - 0.5);
    sim.step();
  }
  const std::optional<cathbox::tool::AneurysmSac> sac = sphere_cap_sac(centre, kSphereR, {0, 0, micro_depth - 1.0 + entry.point_mm.z});
  CoilMetrics metrics(sim, *sac);
  StepTimes times(1 << 16);
  double push = sim.insertion_mm(1);
  double overlap = 0.0;
  double iterations = 0.0, micro_iterations = 0.0;
  const std::uint64_t builds0 = sim.coil_contacts().list_builds();
  const std::uint64_t gathers0 = sim.coil_contacts().gather_calls();
  const std::uint64_t tests0 = sim.coil_contacts().pair_tests();
  const std::uint64_t carries0 = sim.coil_contacts().list_carries();
  for (auto _ : state) {
    push += 0.02;
    sim.set_insertion(1, push);
    times.step(sim);
    iterations += sim.rod(1).last_iterations();
    micro_iterations += sim.rod(0).last_iterations();
    const RodContactField::Overlap o = sim.worst_coil_overlap();
    if (o.diameter_mm > 0.0) overlap = std::max(overlap, o.depth_mm / o.diameter_mm);
  }
  metrics.observe(sim);
  times.report_tail(state, {"micro", "coil"});
  times.report(state);
  state.counters["deployed_mm"] = metrics.figures().deployed_mm;
  state.counters["coil_nodes"] = static_cast<double>(sim.rod(1).node_total() - sim.rod(1).first_free_node());
  state.counters["worst_overlap_pct"] = 100.0 * overlap;
  const auto steps = static_cast<double>(std::max<std::size_t>(1, times.count()));
  state.counters["coil_newton_its"] = iterations / steps;
  state.counters["micro_newton_its"] = micro_iterations / steps;
  // Builds of the rod-rod candidate list per step (worst_coil_overlap above reads it too).
  state.counters["list_builds"] = static_cast<double>(sim.coil_contacts().list_builds() - builds0) / steps;
  state.counters["gathers"] = static_cast<double>(sim.coil_contacts().gather_calls() - gathers0) / steps;
  state.counters["pair_tests"] = static_cast<double>(sim.coil_contacts().pair_tests() - tests0) / steps;
  state.counters["list_carries"] = static_cast<double>(sim.coil_contacts().list_carries() - carries0) / steps;
  state.SetLabel("coil into a 6.4 mm sphere");
}

namespace {

// The released coils' motion in each timed step, and what sleeping (coil_sleep.hpp) made of it.
class ReleasedMotion {
 public:
  ReleasedMotion(Simulator& sim, std::size_t moving)
      : moving_(moving),
        skipped0_(sim.coil_sleep().skipped_steps()),
        wakes0_(sim.coil_sleep().wakes()),
        rest_mm_(sim.coil_sleep_settings().rest_share *
                 (sim.detached_count() > 0 ? sim.detached(0).settings().convergence_mm : RodSettings{}.convergence_mm)) {}
  void before(const Simulator& sim) {
    before_.clear();
    for (std::size_t i = 0; i < sim.detached_count(); ++i) {
      const std::span<const glm::dvec3> x = sim.detached(i).positions();
      before_.insert(before_.end(), x.begin(), x.end());
    }
  }
  void after(const Simulator& sim) {
    double moved = 0.0;
    for (std::size_t i = 0, j = 0; i < sim.detached_count(); ++i) {
      for (const glm::dvec3& p : sim.detached(i).positions()) {
        const double m = glm::length(p - before_[j++]);
        moved = std::max(moved, m);
        restless_ += m > rest_mm_ ? 1.0 : 0.0;
        near(sim, p);
        nodes_ += 1.0;
      }
    }
    largest_mm_ = std::max(largest_mm_, moved);
    sum_mm_ += moved;
    ++steps_;
  }
  // How far the released coils' nodes move in a step (the largest node's), largest and mean;
  // their steps skipped asleep, in % of theirs, and their wakes; the share of their node moves
  // above the sleep's stillness test (a coil sleeps once every node of it has stayed under it,
  // and within its drift limit, for rest_ticks steps).
  void report(benchmark::State& state, const Simulator& sim) const {
    const double steps = std::max(1.0, steps_);
    const double coil_steps = steps * static_cast<double>(std::max<std::size_t>(1, sim.detached_count()));
    state.counters["released_move_max_um"] = 1e3 * largest_mm_;
    state.counters["released_move_mean_um"] = 1e3 * sum_mm_ / steps;
    state.counters["released_asleep_pct"] =
        100.0 * static_cast<double>(sim.coil_sleep().skipped_steps() - skipped0_) / coil_steps;
    state.counters["released_wakes"] = static_cast<double>(sim.coil_sleep().wakes() - wakes0_);
    state.counters["released_restless_pct"] = 100.0 * restless_ / std::max(1.0, nodes_);
    state.counters["released_near_0_5mm_pct"] = 100.0 * near_[0] / std::max(1.0, nodes_);
    state.counters["released_near_1mm_pct"] = 100.0 * near_[1] / std::max(1.0, nodes_);
  }

 private:
  // The share of released nodes an island solve round the moving coil would take: those within
  // 0.5 and 1 mm of its free nodes after the step.
  void near(const Simulator& sim, const glm::dvec3& p) {
    const Rod& rod = sim.rod(moving_);
    double closest = std::numeric_limits<double>::infinity();
    const std::span<const glm::dvec3> x = rod.positions();
    for (std::size_t k = rod.first_free_node(); k < x.size(); ++k) closest = std::min(closest, glm::dot(x[k] - p, x[k] - p));
    near_[0] += closest <= 0.25 ? 1.0 : 0.0;
    near_[1] += closest <= 1.0 ? 1.0 : 0.0;
  }
  std::size_t moving_;
  double near_[2] = {0.0, 0.0};
  std::uint64_t skipped0_, wakes0_;
  double rest_mm_;
  std::vector<glm::dvec3> before_;
  double largest_mm_ = 0.0, sum_mm_ = 0.0, restless_ = 0.0, nodes_ = 0.0, steps_ = 0.0;
};

}  // namespace

// The sphere of BM_StepCoilDeploy already holding 300 mm of coil, a third coil at the
// microcatheter's tip: two coils deployed and detached (~15,000 steps, done outside the timing).
struct PackingScene {
  static constexpr double kSphereR = 3.2;
  static constexpr double kLengths_mm[3] = {150.0, 150.0, 100.0};
  static constexpr double kLoops_mm[3] = {5.0, 4.0, 3.0};
  const glm::dvec3 centre{0.0, 0.0, 20.0};
  const Entry entry{{0, 0, -3}, {0, 0, 1}};
  TubeNetworkWall wall;
  std::optional<Simulator> sim;
  double micro = 0.0;
  std::optional<cathbox::tool::AneurysmSac> sac;
  bool ok = false;  // both coils detached

  PackingScene() {
    wall.add_tube(Tube{{0, 0, -5}, centre, 1.0, 1.0, 0});
    wall.add_tube(Tube{centre, centre + glm::dvec3(0, 0, 1e-3), kSphereR, kSphereR, 1});
    wall.build();
    std::vector<ToolSpec> tools{default_microcatheter()};
    for (int c = 0; c < 3; ++c) {
      tools.push_back(default_coil(kLengths_mm[c], kLoops_mm[c]));
      tools.back().name = "coil " + std::to_string(c + 1);
    }
    sim.emplace(wall, tools, entry);
    micro = centre.z - std::sqrt(kSphereR * kSphereR - 1.0) + 1.0 - entry.point_mm.z;
    drive(0, micro, 0.2);
    for (std::size_t c = 1; c <= 3; ++c) drive(c, micro - 0.5 - 10.0 * static_cast<double>(c - 1), 0.2);
    for (std::size_t c = 1; c <= 2; ++c) {
      drive(c, micro + kLengths_mm[c - 1] + 1.0, 0.02);
      if (sim->detach(c) != DeviceError::kNone) return;
      while (sim->parting(c)) sim->step();  // the hand at rest while its detachment zone parts
      drive(c, micro - 10.0, 0.2);  // its pusher drawn back into the microcatheter
    }
    drive(3, micro - 0.5, 0.2);
    sac = sphere_cap_sac(centre, kSphereR, {0, 0, micro - 1.0 + entry.point_mm.z});
    ok = sac.has_value();
  }
  void drive(std::size_t tool, double to_mm, double per_step_mm) {
    for (double x = sim->insertion_mm(tool); std::abs(to_mm - x) > 1e-9;) {
      x = to_mm > x ? std::min(to_mm, x + per_step_mm) : std::max(to_mm, x - per_step_mm);
      sim->set_insertion(tool, x);
      sim->step();
    }
  }
};

// The scene, built; null (the benchmark skipped) when a coil did not detach.
std::unique_ptr<PackingScene> packing_scene(benchmark::State& state) {
  auto scene = std::make_unique<PackingScene>();
  if (scene->ok) return scene;
  state.SkipWithError("a coil did not detach");
  return nullptr;
}

// The scene above: the third coil pushed at 20 mm/s (0.02 mm a step), steps back to back, each
// waiting for the released coils' job before it returns (the simulator's default).
void BM_StepCoilPacking(benchmark::State& state) {
  const std::unique_ptr<PackingScene> scene = packing_scene(state);
  if (!scene) return;
  Simulator& sim = *scene->sim;
  CoilMetrics metrics(sim, *scene->sac);
  metrics.observe(sim);
  const double packed_pct = 100.0 * metrics.figures().packing_density;
  StepTimes times(1 << 16);
  double push = sim.insertion_mm(3), iterations = 0.0, peak_mN = 0.0;
  const std::uint64_t builds0 = sim.coil_contacts().list_builds();
  const std::uint64_t gathers0 = sim.coil_contacts().gather_calls();
  const std::uint64_t tests0 = sim.coil_contacts().pair_tests();
  const std::uint64_t carries0 = sim.coil_contacts().list_carries();
  ReleasedMotion released(sim, 3);
  for (auto _ : state) {
    push += 0.02;
    sim.set_insertion(3, push);
    released.before(sim);
    times.step(sim);
    released.after(sim);
    iterations += sim.rod(3).last_iterations();
    peak_mN = std::max(peak_mN, std::abs(sim.rod(3).hand_force_mN()));
  }
  metrics.observe(sim);
  times.report_tail(state, {"micro", "coil1", "coil2", "coil3"});
  times.report(state);
  const auto steps = static_cast<double>(std::max<std::size_t>(1, times.count()));
  state.counters["packing_before_pct"] = packed_pct;
  released.report(state, sim);
  state.counters["packing_after_pct"] = 100.0 * metrics.figures().packing_density;
  state.counters["coil_newton_its"] = iterations / steps;
  state.counters["peak_hand_mN"] = peak_mN;
  state.counters["list_builds"] = static_cast<double>(sim.coil_contacts().list_builds() - builds0) / steps;
  state.counters["gathers"] = static_cast<double>(sim.coil_contacts().gather_calls() - gathers0) / steps;
  state.counters["pair_tests"] = static_cast<double>(sim.coil_contacts().pair_tests() - tests0) / steps;
  state.counters["list_carries"] = static_cast<double>(sim.coil_contacts().list_carries() - carries0) / steps;
  state.SetLabel("third coil into a sphere holding 300 mm");
}

// The same push as the haptic loop runs it: a step every 1 ms of the steady clock (the calling
// thread spins until the tick's start, as a rig's haptic thread sleeps), and nothing read of the
// released coils between steps but what a tick reads (released_view). overlap:1 leaves the
// released coils' job running past each step into that wait (Simulator::set_released_overlap, as
// the session sets it); overlap:0 waits for it in the step (the simulator's default). Per tick, its latency: from the tick's start (its deadline, not when the step
// began: a tick started late by the one before carries that) to the step's return, when the hand
// gets its force (`median_us`, `p99_us`, `late_pct`: ticks whose latency passed the 1 ms period);
// and the step's thread CPU. In the wait, when not late, the step's work that can be done ahead
// (Simulator::prepare_next_step: the candidate list built before an edge has moved the whole way
// it covers; `prepared_pct` of the waits, `step_builds_pct` the steps that still built it). The
// results are BM_StepCoilPacking's, bit for bit (`packing_after_pct`, `peak_hand_mN`).
void BM_StepCoilPackingPaced(benchmark::State& state) {
  const std::unique_ptr<PackingScene> scene = packing_scene(state);
  if (!scene) return;
  Simulator& sim = *scene->sim;
  const bool overlap = state.range(0) != 0;
  sim.set_released_overlap(overlap);
  std::vector<double> latency, cpu;
  latency.reserve(1 << 13);
  cpu.reserve(1 << 13);
  double push = sim.insertion_mm(3), peak_mN = 0.0, step_builds = 0.0, prepared = 0.0;
  constexpr auto kTick = std::chrono::microseconds(1000);
  auto due = std::chrono::steady_clock::now() + kTick;
  for (auto _ : state) {
    while (std::chrono::steady_clock::now() < due) {
    }
    push += 0.02;
    sim.set_insertion(3, push);
    const double c0 = thread_cpu_us();
    const std::uint64_t b0 = sim.coil_contacts().list_builds();
    sim.step();
    const auto t1 = std::chrono::steady_clock::now();
    cpu.push_back(thread_cpu_us() - c0);
    latency.push_back(std::chrono::duration<double, std::micro>(t1 - due).count());
    peak_mN = std::max(peak_mN, std::abs(sim.rod(3).hand_force_mN()));
    step_builds += static_cast<double>(sim.coil_contacts().list_builds() - b0);
    // In the wait, as the session's haptic loop does (HapticThread's idle work): not when late.
    if (std::chrono::steady_clock::now() < due + kTick && sim.prepare_next_step()) ++prepared;
    due += kTick;
  }
  sim.settle();
  CoilMetrics metrics(sim, *scene->sac);
  metrics.observe(sim);
  const double late = static_cast<double>(std::count_if(latency.begin(), latency.end(), [](double us) { return us > 1000.0; }));
  state.counters["median_us"] = quantile(latency, 0.5);
  state.counters["p99_us"] = quantile(latency, 0.99);
  state.counters["max_us"] = quantile(latency, 1.0);
  state.counters["late_pct"] = 100.0 * late / static_cast<double>(std::max<std::size_t>(1, latency.size()));
  state.counters["cpu_median_us"] = quantile(cpu, 0.5);
  state.counters["cpu_p99_us"] = quantile(cpu, 0.99);
  const auto steps = static_cast<double>(std::max<std::size_t>(1, latency.size()));
  state.counters["step_builds_pct"] = 100.0 * step_builds / steps;  // the list built in the step
  state.counters["prepared_pct"] = 100.0 * prepared / steps;        // built in the wait before it
  state.counters["packing_after_pct"] = 100.0 * metrics.figures().packing_density;
  state.counters["peak_hand_mN"] = peak_mN;
  state.SetLabel(overlap ? "the same, paced at 1 kHz, the released coils' job running into the wait"
                         : "the same, paced at 1 kHz, each step waiting for the released coils' job");
}

}  // namespace cathbox::bench

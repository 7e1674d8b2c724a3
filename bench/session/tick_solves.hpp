#pragma once
// Where the over-budget ticks of a run at rig speed go (bench_session's CaseAtRigSpeed): each
// tick's thread CPU time split by the rod solves tool::Simulator::step makes (a tool's, or a
// released coil's on its turn), keyed by the rod and the sub-increments its solve ended in
// (Rod::last_substeps: 1 converged whole; 2, 4 ... after an unconverged try). The time before
// a tick's first solve and after its last goes to "the rest" (the session's own work, the
// coupling and the released coils' bookkeeping).
#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "../bench_samples.hpp"
#include "tool/simulator.hpp"

namespace cathbox::bench {

class TickSolves final : public tool::Simulator::SolveObserver {
 public:
  TickSolves() { tick_.reserve(64); }
  // A tick begins: its solves are kept until end_tick (each timed from the step's start or the
  // solve before it).
  void begin_tick() { tick_.clear(); }
  void step_begins() override { last_us_ = thread_cpu_us(); }
  void solved(bool released, std::size_t index, const tool::Rod& rod) override {
    const double now = thread_cpu_us();
    tick_.push_back({Key{released, index, rod.last_substeps()}, now - last_us_});
    last_us_ = now;
  }
  // The tick ended having used `cpu_us`; over `budget_us`, its solves are added to the totals.
  void end_tick(double cpu_us, double budget_us) {
    if (cpu_us <= budget_us) return;
    double solves = 0.0;
    for (const auto& [key, us] : tick_) {
      Total& t = totals_[key];
      t.us += us;
      ++t.count;
      solves += us;
    }
    rest_us_ += std::max(0.0, cpu_us - solves);
    over_us_ += cpu_us;
  }
  // Counters: the over-budget ticks' CPU in released coils' solves and in solves that ended in
  // parts, in % of it; the largest shares to stderr ("rod x parts: solves, ms").
  void report(benchmark::State& state, const std::string& case_name, const tool::Simulator& sim) const {
    double released = 0.0, parted = 0.0;
    std::vector<std::pair<Key, Total>> order(totals_.begin(), totals_.end());
    for (const auto& [key, t] : order) {
      if (std::get<0>(key)) released += t.us;
      if (std::get<2>(key) > 1) parted += t.us;
    }
    const double over = std::max(over_us_, 1e-9);
    state.counters["over_1ms_released_pct"] = 100.0 * released / over;
    state.counters["over_1ms_parted_pct"] = 100.0 * parted / over;
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.second.us > b.second.us; });
    std::fprintf(stderr, "%s: over-budget ticks' CPU %.0f ms by solve (rod x parts: solves, ms):", case_name.c_str(),
                 1e-3 * over_us_);
    for (std::size_t i = 0; i < std::min<std::size_t>(8, order.size()); ++i) {
      const auto& [released_coil, index, parts] = order[i].first;
      const std::string who = released_coil ? "released coil " + std::to_string(index + 1) : sim.rod(index).spec().name;
      std::fprintf(stderr, " %s x%d: %ld, %.0f;", who.c_str(), parts, order[i].second.count, 1e-3 * order[i].second.us);
    }
    std::fprintf(stderr, " the rest %.0f\n", 1e-3 * rest_us_);
  }

 private:
  using Key = std::tuple<bool, std::size_t, int>;  // released, index, parts
  struct Total {
    double us = 0.0;
    long count = 0;
  };
  std::vector<std::pair<Key, double>> tick_;
  std::map<Key, Total> totals_;
  double last_us_ = 0.0, rest_us_ = 0.0, over_us_ = 0.0;
};

}  // namespace cathbox::bench

#pragma once
// Per-step timing of bench_tool's step benchmarks: wall and thread-CPU time, Newton iterations,
// preemptions, page faults and wall probes of each step; medians, p99s and the tail as counters.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "../bench_samples.hpp"
#include "counting_wall.hpp"
#include "tool/simulator.hpp"

namespace cathbox::bench {

// Wall and thread-CPU time of each step; median and p99 as counters, and the same of the steps
// in which every solved rod converged (the rest end at the Newton iteration cap).
class StepTimes {
 public:
  explicit StepTimes(std::size_t steps) {
    wall_.reserve(steps);
    cpu_.reserve(steps);
    unconverged_.reserve(steps);
    substepped_.reserve(steps);
    its_.reserve(3 * steps);
    switches_.reserve(steps);
    faults_.reserve(steps);
    work_.reserve(steps);
    released_.reserve(steps);
    builds_.reserve(steps);
  }
  // Times one sim.step() and keeps each rod's Newton iterations in it.
  void step(tool::Simulator& sim) {
    const Work before = total_work(sim);
    const std::uint64_t builds0[2] = {sim.coil_contacts().list_builds(), sim.released_contacts().list_builds()};
    const ThreadUsage u0 = thread_usage();
    const double c0 = thread_cpu_us();
    const auto t0 = std::chrono::steady_clock::now();
    sim.step();
    const auto t1 = std::chrono::steady_clock::now();
    cpu_.push_back(thread_cpu_us() - c0);
    wall_.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    const ThreadUsage u1 = thread_usage();
    switches_.push_back(static_cast<int>(u1.preemptions - u0.preemptions));
    faults_.push_back(static_cast<int>(u1.faults - u0.faults));
    released_.push_back(sim.released_timing());
    builds_.push_back({static_cast<double>(sim.coil_contacts().list_builds() - builds0[0]),
                       static_cast<double>(sim.released_contacts().list_builds() - builds0[1])});
    rods_ = sim.tool_count();
    bool unconverged = false, substepped = false;
    for (std::size_t t = 0; t < rods_; ++t) {
      const tool::Rod& rod = sim.rod(t);
      its_.push_back(rod.last_iterations());
      unconverged = unconverged || (rod.first_free_node() < rod.node_total() && !rod.converged());
      substepped = substepped || rod.last_substeps() > 1;
    }
    unconverged_.push_back(unconverged ? 1 : 0);
    substepped_.push_back(substepped ? 1 : 0);
    Work step = total_work(sim);
    for (std::size_t i = 0; i < step.size(); ++i) step[i] -= before[i];
    work_.push_back(step);
    if (wall_probes_ != nullptr) {
      probes_.push_back(static_cast<double>(wall_probes_->probes() - probes_seen_));
      probes_seen_ = wall_probes_->probes();
    }
  }
  // Keep the wall probes each step makes (`probes`, and `tail_probes` over the tail steps).
  void count_probes(const CountingWall& wall) {
    wall_probes_ = &wall;
    probes_seen_ = wall.probes();
  }
  [[nodiscard]] double last_wall_us() const { return wall_.back(); }
  [[nodiscard]] std::size_t count() const { return wall_.size(); }
  // Sorts v in place (callers read it sorted after) and takes its q-quantile.
  static double pick(std::vector<double>& v, double q) {
    std::sort(v.begin(), v.end());
    return cathbox::bench::quantile_sorted(v, q);
  }
  // What the tail is made of: over the steps at or above the thread-CPU p99, each rod's mean
  // Newton iterations (`tail_its_<name>`) beside its mean over all steps (`its_<name>`), the
  // share of them the scheduler preempted (`tail_preempted_pct`, of all steps `preempted_pct`:
  // another process ran on the core mid-step, and the step's thread CPU time carries the cache
  // refill; a long step is likelier to be preempted, so under load the tail's share is high
  // whatever made the step long) and their page faults. Call it before report(), which sorts
  // the times. `tail_unconverged_pct`: the share of the tail's steps in which a rod ended
  // unconverged; `substepped_pct` / `tail_substepped_pct`: of all steps / the tail's, those in
  // which a rod's unconverged solve was done again in sub-steps (Rod::last_substeps).
  void report_tail(benchmark::State& state, const std::vector<std::string>& names, const std::string& prefix = "") const {
    if (cpu_.empty() || rods_ == 0 || its_.size() != cpu_.size() * rods_) return;
    std::vector<double> sorted = cpu_;
    const double p99 = pick(sorted, 0.99);
    std::size_t tail_steps = 0, preempted = 0, faults = 0, all_preempted = 0, unconverged = 0;
    std::size_t substepped = 0, all_substepped = 0;
    for (std::size_t k = 0; k < cpu_.size(); ++k) {
      all_preempted += switches_[k] > 0 ? 1 : 0;
      all_substepped += substepped_[k];
      if (cpu_[k] < p99) continue;
      ++tail_steps;
      unconverged += k < unconverged_.size() ? unconverged_[k] : 0;
      substepped += substepped_[k];
      preempted += switches_[k] > 0 ? 1 : 0;
      faults += static_cast<std::size_t>(faults_[k]);
    }
    const double tail_n = static_cast<double>(std::max<std::size_t>(1, tail_steps));
    state.counters[prefix + "preempted_pct"] = 100.0 * static_cast<double>(all_preempted) / static_cast<double>(cpu_.size());
    state.counters[prefix + "tail_preempted_pct"] = 100.0 * static_cast<double>(preempted) / tail_n;
    state.counters[prefix + "tail_faults"] = static_cast<double>(faults) / tail_n;
    state.counters[prefix + "tail_unconverged_pct"] = 100.0 * static_cast<double>(unconverged) / tail_n;
    state.counters[prefix + "substepped_pct"] = 100.0 * static_cast<double>(all_substepped) / static_cast<double>(cpu_.size());
    state.counters[prefix + "tail_substepped_pct"] = 100.0 * static_cast<double>(substepped) / tail_n;
    for (std::size_t t = 0; t < rods_ && t < names.size(); ++t) {
      double all = 0.0, tail = 0.0;
      for (std::size_t k = 0; k < cpu_.size(); ++k) {
        const double its = its_[k * rods_ + t];
        all += its;
        if (cpu_[k] >= p99) tail += its;
      }
      state.counters[prefix + "its_" + names[t]] = all / static_cast<double>(cpu_.size());
      state.counters[prefix + "tail_its_" + names[t]] = tail / tail_n;
    }
    // The solver's work a step, summed over the rods (deterministic, unlike the times): the
    // factorisations, block rows factored, solves and line-search tries, over all steps and the
    // tail (`tail_factors` ...).
    if (work_.size() == cpu_.size()) {
      static const char* const kWork[] = {"factors", "rows_factored", "solves", "line_tries"};
      for (std::size_t i = 0; i < std::size(kWork); ++i) {
        double all = 0.0, tail = 0.0;
        for (std::size_t k = 0; k < cpu_.size(); ++k) {
          all += work_[k][i];
          if (cpu_[k] >= p99) tail += work_[k][i];
        }
        state.counters[prefix + kWork[i]] = all / static_cast<double>(cpu_.size());
        state.counters[prefix + "tail_" + kWork[i]] = tail / tail_n;
      }
    }
    report_released(state, p99, prefix);
    if (probes_.size() == cpu_.size()) {
      double all = 0.0, tail = 0.0;
      for (std::size_t k = 0; k < cpu_.size(); ++k) {
        all += probes_[k];
        if (cpu_[k] >= p99) tail += probes_[k];
      }
      state.counters[prefix + "probes"] = all / static_cast<double>(cpu_.size());
      state.counters[prefix + "tail_probes"] = tail / tail_n;
    }
  }
  // `unconverged_pct`: the steps in which a solved rod ended unconverged; `cpu_median_converged_us`
  // and `cpu_p99_converged_us`: the thread CPU of the others.
  void report(benchmark::State& state, const std::string& prefix = "") {
    if (unconverged_.size() == cpu_.size() && !cpu_.empty()) {
      std::vector<double> converged;
      for (std::size_t k = 0; k < cpu_.size(); ++k) {
        if (unconverged_[k] == 0) converged.push_back(cpu_[k]);
      }
      state.counters[prefix + "unconverged_pct"] =
          100.0 * static_cast<double>(cpu_.size() - converged.size()) / static_cast<double>(cpu_.size());
      if (!converged.empty()) {
        state.counters[prefix + "cpu_median_converged_us"] = pick(converged, 0.5);
        state.counters[prefix + "cpu_p99_converged_us"] = pick(converged, 0.99);
      }
    }
    state.counters[prefix + "median_us"] = pick(wall_, 0.5);
    state.counters[prefix + "p99_us"] = pick(wall_, 0.99);
    state.counters[prefix + "cpu_median_us"] = pick(cpu_, 0.5);
    state.counters[prefix + "cpu_p99_us"] = pick(cpu_, 0.99);
  }
  // The times of another run's steps added to these (a benchmark's phases, then all of them).
  void add(const StepTimes& other) {
    wall_.insert(wall_.end(), other.wall_.begin(), other.wall_.end());
    cpu_.insert(cpu_.end(), other.cpu_.begin(), other.cpu_.end());
    unconverged_.insert(unconverged_.end(), other.unconverged_.begin(), other.unconverged_.end());
  }

 private:
  std::vector<double> wall_, cpu_;
  std::vector<int> its_;  // Newton iterations, rods_ per step
  std::vector<std::uint8_t> unconverged_;  // per step: 1 when a solved rod ended unconverged
  std::vector<std::uint8_t> substepped_;   // per step: 1 when a rod was solved again in sub-steps
  std::vector<int> switches_, faults_;  // involuntary context switches and page faults per step
  std::size_t rods_ = 0;
  const CountingWall* wall_probes_ = nullptr;
  std::uint64_t probes_seen_ = 0;
  std::vector<double> probes_;  // wall probes per step
  using Work = std::array<double, 4>;  // factorisations, rows factored, solves, line-search tries
  std::vector<Work> work_;              // per step, summed over the rods

  std::vector<tool::Simulator::ReleasedTiming> released_;  // per step
  std::vector<std::array<double, 2>> builds_;  // per step: list builds of the tools' field, the job's

  // The released coils' job (Simulator::released_timing) over the steps in which it ran: its
  // median run and the step's median wait for it (`released_run_median_us`,
  // `released_wait_median_us`), and their means over the tail (`tail_released_run_us`,
  // `tail_released_wait_us`; the tail: steps at or above the thread-CPU p99). A wait is time the
  // calling thread spent done with the attached tools while the job still ran. And the
  // candidate-list builds a step (RodContactField::list_builds) of the job's field, over all
  // steps and the tail (`released_list_builds`, `tail_released_list_builds`), and of the tools'
  // field over the tail (`tail_list_builds`; over all steps the bench's own `list_builds`).
  void report_released(benchmark::State& state, double p99, const std::string& prefix) const {
    if (released_.size() != cpu_.size() || builds_.size() != cpu_.size()) return;
    std::vector<double> run, wait;
    double tail_run = 0.0, tail_wait = 0.0, tail_n = 0.0, job_builds = 0.0, tail_builds[2] = {0.0, 0.0};
    for (std::size_t k = 0; k < cpu_.size(); ++k) {
      job_builds += builds_[k][1];
      if (cpu_[k] >= p99) tail_builds[0] += builds_[k][0], tail_builds[1] += builds_[k][1], tail_n += 1.0;
      if (released_[k].run_us <= 0.0) continue;
      run.push_back(released_[k].run_us);
      wait.push_back(released_[k].wait_us);
      if (cpu_[k] >= p99) tail_run += released_[k].run_us, tail_wait += released_[k].wait_us;
    }
    if (run.empty()) return;
    tail_n = std::max(1.0, tail_n);
    state.counters[prefix + "released_run_median_us"] = pick(run, 0.5);
    state.counters[prefix + "released_wait_median_us"] = pick(wait, 0.5);
    state.counters[prefix + "tail_released_run_us"] = tail_run / tail_n;
    state.counters[prefix + "tail_released_wait_us"] = tail_wait / tail_n;
    state.counters[prefix + "released_list_builds"] = job_builds / static_cast<double>(cpu_.size());
    state.counters[prefix + "tail_released_list_builds"] = tail_builds[1] / tail_n;
    state.counters[prefix + "tail_list_builds"] = tail_builds[0] / tail_n;
  }

  static Work total_work(const tool::Simulator& sim) {
    Work sum{};
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      const tool::Rod::SolverWork w = sim.rod(t).solver_work();
      sum[0] += static_cast<double>(w.factors), sum[1] += static_cast<double>(w.rows_factored);
      sum[2] += static_cast<double>(w.solves), sum[3] += static_cast<double>(w.line_tries);
    }
    return sum;
  }
};

}  // namespace cathbox::bench

#pragma once
// bench_fluoro's haptic loop: the real session tick (simulator, hand, contrast transport,
// fluoroscopy unit) of cases/neuro.case on its own 1 kHz thread beside the renderer, and each
// benchmark's share of it (ticks run and dropped, its thread's CPU time).
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "session/session.hpp"

namespace cathbox::bench {

class HapticLoop {
 public:
  // Before a benchmark's timed loop: a run going (a new one if the last has ended).
  bool ensure_running(std::string& error);
  // Ticks run and dropped so far, over all runs.
  [[nodiscard]] std::int64_t ticks() const { return ticks_done_ + (session_ ? session_->ticks() : 0); }
  [[nodiscard]] std::int64_t dropped() const { return dropped_done_ + (session_ ? session_->dropped_ticks() : 0); }
  [[nodiscard]] std::int64_t cpu_us() const { return cpu_done_us_ + (session_ ? session_->haptic_cpu_time_us() : 0); }
  // Runs started (more than one: a run ended and the next was loaded).
  [[nodiscard]] int starts() const { return starts_; }
  // The scheduling the loop's thread obtained (SCHED_FIFO, nice or normal).
  [[nodiscard]] std::string scheduling() const { return session_ ? session_->haptic_scheduling() : scheduling_; }
  void retire();

 private:
  std::unique_ptr<session::Session> session_;
  std::int64_t ticks_done_ = 0;
  std::int64_t dropped_done_ = 0;
  std::int64_t cpu_done_us_ = 0;
  std::string scheduling_ = "not started";
  int starts_ = 0;
};

// The program's one loop.
HapticLoop& haptic();

// A benchmark's share of the haptic loop: its ticks and drops from construction to report().
class HapticWindow {
 public:
  explicit HapticWindow(benchmark::State& state);
  // Between frames (not timed): a new run when the scripted hand's has ended.
  void keep(benchmark::State& state);
  void report(benchmark::State& state) const;

 private:
  std::int64_t ticks0_ = 0;
  std::int64_t dropped0_ = 0;
  std::int64_t cpu0_us_ = 0;
  int starts0_ = 0;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace cathbox::bench

#pragma once
// Per-call timing for the Google Benchmark programs: each timed call's wall and thread-CPU
// time (and optionally the process's CPU time), reported as median and p99 counters
// (median_<unit>, p99_<unit>, cpu_median_<unit>, cpu_p99_<unit>), since a budget is about the typical and the worst call, not the mean.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <time.h>

#include <benchmark/benchmark.h>

namespace cathbox::bench {

// CPU time of the calling thread, µs.
inline double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

// The calling thread's page faults (minor and major) and involuntary context switches so far:
// the difference across a call is what it took (a fresh page, a preemption).
struct ThreadUsage {
  long faults = 0, preemptions = 0;
};
inline ThreadUsage thread_usage() {
  rusage r{};
  getrusage(RUSAGE_THREAD, &r);
  return {r.ru_minflt + r.ru_majflt, r.ru_nivcsw};
}

// The q-quantile (0..1) of sorted values: the value at rank floor(q n), the last for q = 1; 0
// when there are none. Every median_* and p99_* counter of the benchmarks is this one.
inline double quantile_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sorted.size())))];
}
inline double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  return quantile_sorted(values, q);
}
// The q-quantile at rank floor(q (n - 1)) (bench_session's tick counters keep this rank).
inline double quantile_below(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}
// The p-th percentile (0..100), interpolated linearly between ranks (the centre load's latencies).
inline double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = p / 100.0 * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const auto hi = std::min(values.size() - 1, lo + 1);
  return values[lo] + (values[hi] - values[lo]) * (rank - static_cast<double>(lo));
}

class Samples {
 public:
  // unit "us" or "ms": what the counters are in.
  explicit Samples(std::string unit = "us") : unit_(std::move(unit)), scale_(unit_ == "ms" ? 1e-3 : 1.0) {}

  template <typename F>
  void time(F&& f) {
    const double c0 = thread_cpu_us();
    const double p0 = process_cpu_us();
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    cpu_.push_back((thread_cpu_us() - c0) * scale_);
    process_.push_back((process_cpu_us() - p0) * scale_);
    wall_.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() * scale_);
  }

  void report(benchmark::State& state) {
    std::sort(wall_.begin(), wall_.end());
    std::sort(cpu_.begin(), cpu_.end());
    state.counters["median_" + unit_] = pick(wall_, 0.5);
    state.counters["p99_" + unit_] = pick(wall_, 0.99);
    state.counters["cpu_median_" + unit_] = pick(cpu_, 0.5);
    state.counters["cpu_p99_" + unit_] = pick(cpu_, 0.99);
    if (report_process_) {
      std::sort(process_.begin(), process_.end());
      state.counters["process_cpu_median_" + unit_] = pick(process_, 0.5);
      state.counters["process_cpu_p99_" + unit_] = pick(process_, 0.99);
    }
  }
  // Also report the whole process's CPU time per call (for work done by other threads, e.g.
  // a software rasteriser's workers).
  void report_process_cpu() { report_process_ = true; }

 private:
  static double process_cpu_us() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
  }
  static double pick(const std::vector<double>& sorted, double q) { return quantile_sorted(sorted, q); }
  std::string unit_;
  double scale_ = 1.0;
  bool report_process_ = false;
  std::vector<double> wall_, cpu_, process_;
};

}  // namespace cathbox::bench

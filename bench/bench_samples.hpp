#pragma once
// Per-call timing for the Google Benchmark programs: each timed call's wall and thread-CPU
// time (and optionally the process's CPU time), reported as median and p99 counters
// (median_<unit>, p99_<unit>, cpu_median_<unit>, cpu_p99_<unit>), since a budget is about the typical and the worst call, not the mean.
#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include <time.h>

#include <benchmark/benchmark.h>

namespace cathbox::bench {

class Samples {
 public:
  // unit "us" or "ms": what the counters are in.
  explicit Samples(std::string unit = "us") : unit_(std::move(unit)), scale_(unit_ == "ms" ? 1e-3 : 1.0) {}

  template <typename F>
  void time(F&& f) {
    const double c0 = cpu_us(CLOCK_THREAD_CPUTIME_ID);
    const double p0 = cpu_us(CLOCK_PROCESS_CPUTIME_ID);
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    cpu_.push_back((cpu_us(CLOCK_THREAD_CPUTIME_ID) - c0) * scale_);
    process_.push_back((cpu_us(CLOCK_PROCESS_CPUTIME_ID) - p0) * scale_);
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
  static double cpu_us(clockid_t clock) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
  }
  static double pick(const std::vector<double>& v, double q) {
    return v.empty() ? 0.0 : v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
  }
  std::string unit_;
  double scale_ = 1.0;
  bool report_process_ = false;
  std::vector<double> wall_, cpu_, process_;
};

}  // namespace cathbox::bench

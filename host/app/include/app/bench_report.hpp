#pragma once
// The trainer's --bench: frame intervals and render work per frame (median, p99), CPU time per
// frame of the render thread and of all rendering threads (the process less the haptic thread,
// so including Mesa's rasteriser workers) and the haptic rate over the same window.
#include <cstdint>
#include <string>

#include "app/frame_stats.hpp"

namespace cathbox::app {

struct BenchPoint {
  std::int64_t time_us = 0;
  std::int64_t haptic_ticks = 0;
  std::int64_t process_cpu_us = 0;
  std::int64_t render_cpu_us = 0;
  std::int64_t haptic_cpu_us = 0;
  // The process's and the calling (render) thread's CPU time now.
  static BenchPoint now(std::int64_t time_us, std::int64_t haptic_ticks, std::int64_t haptic_cpu_us);
};

struct BenchContext {
  int width = 0;
  int height = 0;
  std::string case_name;
  std::size_t detail_triangles = 0;
  std::size_t overview_triangles = 0;
  std::string renderer;
  int fps_cap = 0;   // > 0 when frames were paced
  std::size_t global_triangles = 0;
  std::size_t local_triangles = 0;
  std::int64_t dropped_ticks = 0;
  std::string scheduling;
};

void print_bench(const BenchContext& context, const FrameStats& intervals, const FrameStats& work,
                 const BenchPoint& start, const BenchPoint& end);

}  // namespace cathbox::app

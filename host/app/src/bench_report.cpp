#include "app/bench_report.hpp"

#include <algorithm>
#include <cstdio>

#include "session/clock.hpp"

namespace cathbox::app {

BenchPoint BenchPoint::now(std::int64_t time_us, std::int64_t haptic_ticks, std::int64_t haptic_cpu_us) {
  return {time_us, haptic_ticks, session::process_cpu_time_us(), session::thread_cpu_time_us(), haptic_cpu_us};
}

void print_bench(const BenchContext& c, const FrameStats& stats, const FrameStats& work, const BenchPoint& start,
                 const BenchPoint& end) {
  const double seconds = static_cast<double>(end.time_us - start.time_us) * 1e-6;
  std::printf("bench: %dx%d, %s: %zu triangles (global view %zu), renderer %s\n", c.width, c.height,
              c.case_name.c_str(), c.detail_triangles, c.overview_triangles, c.renderer.c_str());
  const std::string pacing = c.fps_cap > 0 ? "paced at " + std::to_string(c.fps_cap) + " Hz" : "uncapped";
  std::printf("frames: %zu in %.2f s (%s): %.1f fps, frame interval median %.2f ms, p99 %.2f ms\n", stats.count(),
              seconds, pacing.c_str(), stats.mean_fps(), stats.percentile_us(50) * 1e-3, stats.percentile_us(99) * 1e-3);
  std::printf("frame time (render work, poll to swap): median %.2f ms, p99 %.2f ms -> %.0f fps possible\n",
              work.percentile_us(50) * 1e-3, work.percentile_us(99) * 1e-3,
              work.percentile_us(50) > 0 ? 1e6 / work.percentile_us(50) : 0.0);
  // CPU time per frame is what the machine's load does not change.
  const double frames = static_cast<double>(std::max<std::size_t>(1, stats.count()));
  const double haptic_cpu_ms = static_cast<double>(end.haptic_cpu_us - start.haptic_cpu_us) * 1e-3;
  std::printf("CPU per frame: render thread %.2f ms, all rendering threads %.2f ms; haptic thread %.1f %% of a core\n",
              static_cast<double>(end.render_cpu_us - start.render_cpu_us) * 1e-3 / frames,
              (static_cast<double>(end.process_cpu_us - start.process_cpu_us) * 1e-3 - haptic_cpu_ms) / frames,
              100.0 * haptic_cpu_ms / (seconds * 1e3));
  std::printf("triangles submitted per frame: global view %zu, local view %zu\n", c.global_triangles, c.local_triangles);
  std::printf("haptic: %.1f Hz over the same window (%lld ticks, %lld dropped in the run), thread %s\n",
              static_cast<double>(end.haptic_ticks - start.haptic_ticks) / seconds,
              static_cast<long long>(end.haptic_ticks - start.haptic_ticks), static_cast<long long>(c.dropped_ticks),
              c.scheduling.c_str());
}

}  // namespace cathbox::app

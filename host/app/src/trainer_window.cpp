// TrainerApp's window run: the frame loop that paces, advances and draws a live or replayed run
// in the GLFW window, and its figures (--frames, --bench-seconds).
#include <algorithm>
#include <cstdio>

#include "app/bench_report.hpp"
#include "app/carm_panel.hpp"
#include "app/frame_stats.hpp"
#include "app/gl.hpp"
#include "app/gl_window.hpp"
#include "app/replay_panel.hpp"
#include "app/screenshot_writer.hpp"
#include "app/server_link.hpp"
#include "app/trainer_app.hpp"
#include "app/trainer_ui.hpp"
#include "base/exit_codes.hpp"
#include "session/thread_priority.hpp"

namespace cathbox::app {
namespace {
constexpr int kWarmupFrames = 20;
constexpr std::int64_t kReplayBudget_us = 25'000;  // CPU per frame a replay may spend catching up
}  // namespace


// The window's frame loop: its clock, pacing and figures.
struct TrainerApp::FrameLoop {
  device::SystemClock clock;
  bool virtual_time = false;  // --frames: each frame advances the run by --sim-ms-per-frame
  bool timed = false;         // --bench-seconds
  std::int64_t start_us = 0;
  std::int64_t last_us = 0;
  std::int64_t frame_period_us = 0;  // 0: not paced
  std::int64_t next_frame_us = 0;
  std::int64_t frame_dt_us = 0;
  std::int64_t now_us = 0;  // the end of the last frame
  FrameStats stats;
  FrameStats work;
  BenchPoint bench_start;
  double fps = 0.0;
  int frame = 0;
  [[nodiscard]] bool last_frame(int frames) const { return frames > 0 && frame >= frames; }
};

// What the trainee asked for in one frame, through the keys, the UI and the panels.
struct TrainerApp::FrameActions {
  InputActions input;
  UiActions ui;
  CArmPanelActions carm;
  ReplayPanelActions replay;
};

namespace {
constexpr int kNextFrame = -1;  // run_frame: go on
constexpr int kEndLoop = -2;    // run_frame: the run is over (last frame, time up)
}  // namespace

int TrainerApp::run_window() {
  const CaseChoice choice = choose();
  current_case_ = choice.catalog_index;
  if (options_.replay.empty() && choice.path.empty()) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", choice.error.c_str());
    return base::kExitBadInput;
  }
  if (const int failed = open_window(choice.path); failed != base::kExitOk) return failed;
  FrameLoop loop;
  start_window_run(loop);
  while (!window_->should_close()) {
    const int step = run_frame(loop, choice.path);
    if (step == kEndLoop) break;
    if (step != kNextFrame) return step;
  }
  finish_window_run(loop);
  return base::kExitOk;
}

// Says what runs, starts it and the loop's clock.
void TrainerApp::start_window_run(FrameLoop& loop) {
  loop.timed = options_.bench_seconds > 0.0;
  std::printf("cathbox-trainer: %s, %s: %s\n", current().scene().name.c_str(), replay_ ? "replay" : "hand",
              current().hand_description().c_str());
  std::fflush(stdout);
  loop.virtual_time = options_.frames > 0;
  if (live_ && !loop.virtual_time) live_->start();
  if (replay_) replay_->play();
  // The software rasteriser's workers yield to the haptic thread (no effect on a GPU driver).
  (void)session::ThreadPriority::lower_threads_named("llvmpipe", 10);
  loop.start_us = loop.clock.now_us();
  loop.last_us = loop.clock.now_us();
  // Without vsync (Xvfb, bench) frames are paced as a display would; headless frames are not.
  loop.frame_period_us = (options_.headless || loop.timed) && options_.fps_cap > 0 && !loop.virtual_time
                             ? 1'000'000 / options_.fps_cap
                             : 0;
  loop.next_frame_us = loop.clock.now_us();
}

// One frame: the run advanced, the views and panels drawn, the frame timed, then what the
// trainee asked for applied. kNextFrame, kEndLoop, or the exit code with its line printed.
int TrainerApp::run_frame(FrameLoop& loop, const std::string& chosen_path) {
  if (loop.frame_period_us > 0) {
    loop.clock.sleep_until_us(loop.next_frame_us);
    loop.next_frame_us = std::max(loop.next_frame_us + loop.frame_period_us, loop.clock.now_us());
  }
  const std::int64_t frame_start_us = loop.clock.now_us();
  glfwPollEvents();
  if (live_ && loop.virtual_time) live_->step_virtual(options_.sim_ms_per_frame);
  if (replay_) {
    const bool ok = loop.virtual_time ? replay_->advance(options_.sim_ms_per_frame * 1000LL, -1)
                                      : replay_->advance(loop.frame_dt_us, kReplayBudget_us);
    if (!ok) {
      std::fprintf(stderr, "cathbox-trainer: %s\n", replay_->error().c_str());
      return base::kExitBadInput;
    }
  }
  session::Session& s = current();
  s.snapshots().acquire();
  const session::SceneSnapshot& snap = s.snapshots().read_slot();
  follow_wall(s, snap.wall_generation, snap.wall_pressure_kPa, loop.virtual_time);
  ui_->drain(s.events());
  if (link_ && live_) link_->publish(snap);
  FrameActions actions;
  if (const int drawn = draw_frame(loop, s, snap, actions); drawn != kNextFrame) return drawn;
  if (time_frame(loop, s, frame_start_us)) return kEndLoop;
  // What the trainee asked for (the session may be replaced: nothing of `s` is used after).
  if (live_) post_live_actions(actions.ui, actions.input, actions.carm, snap, loop.now_us);
  if (!switch_run(actions.ui, actions.replay, chosen_path, loop.virtual_time)) return base::kExitBadInput;
  return kNextFrame;
}

// The input handled, the views and panels drawn, the screenshot of the last frame written, the
// buffers swapped: kNextFrame, or the exit code with its line printed.
int TrainerApp::draw_frame(FrameLoop& loop, session::Session& s, const session::SceneSnapshot& snap, FrameActions& actions) {
  int fw = 0;
  int fh = 0;
  window_->framebuffer_size(fw, fh);
  const ScreenLayout layout = ScreenLayout::for_window(fw, fh);
  ui_->begin_frame();
  const InputController::Pick pick = [&s](const glm::vec3& o, const glm::vec3& d) { return s.scene().pick(o, d); };
  actions.input = input_.handle(window_->handle(), *ui_, layout, camera_, settings_, pick, replay_ ? nullptr : &keyboard_);
  if (actions.input.frame_camera) frame_camera();
  renderer_->clear(fw, fh);
  renderer_->update_tools(snap, settings_);
  render_main_view(layout, fh, snap);
  renderer_->render_local(layout.local, fh, snap);
  ScreenLayout ui_layout = layout;
  actions.carm = draw_carm(layout, snap, ui_layout);
  actions.ui = ui_->draw(ui_layout, snap, ui_status(s, snap, loop.fps), catalog_, current_case_, settings_);
  if (replay_) actions.replay = replay_panel_->draw(layout.global, *replay_);
  ui_->end_frame();
  ++loop.frame;
  if (loop.last_frame(options_.frames) && !options_.screenshot.empty()) {
    const ScreenshotScene shot{layout, ui_->hud_rect(), camera_.view(), camera_.projection(layout.global.aspect()),
                               s.scene().vessel_file, s.scene().target_mm, s.scene().target_radius_mm};
    if (base::Status<> written = write_screenshot(options_.screenshot, shot, snap, fw, fh); !written) {
      std::fprintf(stderr, "cathbox-trainer: %s\n", written.error().message.c_str());
      return base::kExitFailure;
    }
  }
  window_->swap_buffers();
  return kNextFrame;
}

// The frame's time into the rate shown and the bench's figures; true when the run is over (the
// last --frames frame, the bench's or --max-seconds' time up).
bool TrainerApp::time_frame(FrameLoop& loop, session::Session& s, std::int64_t frame_start_us) {
  const std::int64_t now = loop.clock.now_us();
  loop.now_us = now;
  loop.frame_dt_us = now - loop.last_us;
  loop.last_us = now;
  loop.fps = loop.frame_dt_us > 0 ? 0.9 * loop.fps + 0.1 * 1e6 / static_cast<double>(loop.frame_dt_us) : loop.fps;
  if (loop.timed && loop.frame == kWarmupFrames) {
    loop.bench_start = BenchPoint::now(now, s.ticks(), s.haptic_cpu_time_us());
  } else if (loop.timed && loop.frame > kWarmupFrames) {
    loop.stats.add(loop.frame_dt_us);
    loop.work.add(now - frame_start_us);
    if (static_cast<double>(now - loop.bench_start.time_us) >= options_.bench_seconds * 1e6) return true;
  }
  if (loop.last_frame(options_.frames)) return true;
  return !loop.timed && options_.max_seconds > 0.0 && static_cast<double>(now - loop.start_us) >= options_.max_seconds * 1e6;
}

// Stops the run and prints the bench's figures (--bench-seconds) or the run's metrics.
void TrainerApp::finish_window_run(FrameLoop& loop) {
  const BenchPoint bench_end = BenchPoint::now(loop.clock.now_us(), current().ticks(), current().haptic_cpu_time_us());
  current().stop();
  if (loop.timed) {
    BenchContext c;
    c.width = options_.width;
    c.height = options_.height;
    c.case_name = current().scene().name;
    c.detail_triangles = renderer_->detail_triangles();
    c.overview_triangles = renderer_->overview_triangles();
    c.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    c.fps_cap = loop.frame_period_us > 0 ? options_.fps_cap : 0;
    c.global_triangles = renderer_->last_global_triangles();
    c.local_triangles = renderer_->last_local_triangles();
    c.dropped_ticks = current().dropped_ticks();
    c.scheduling = current().haptic_scheduling();
    print_bench(c, loop.stats, loop.work, loop.bench_start, bench_end);
  } else if (!options_.headless && live_) {
    std::printf("end of run\n%s", session::MetricsCollector::format(live_->metrics()).c_str());
  }
}

}  // namespace cathbox::app

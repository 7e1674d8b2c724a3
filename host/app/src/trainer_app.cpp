#include "app/trainer_app.hpp"

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <glm/gtc/type_ptr.hpp>

#include "app/clock.hpp"
#include "app/frame_capture.hpp"
#include "app/frame_stats.hpp"
#include "app/gl.hpp"
#include "app/gl_window.hpp"
#include "app/png_writer.hpp"
#include "app/thread_priority.hpp"
#include "app/trainer_ui.hpp"

namespace cathbox::app {
namespace {

std::int64_t cpu_time_us(clockid_t which) {
  timespec ts{};
  clock_gettime(which, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1000;
}

const std::vector<std::string> kCaseExtensions = {".case", ".hclm"};
constexpr const char* kDefaultCase = "neuro_right_ica.case";
constexpr const char* kPreferredCase = "neuro";

void print_matrix(std::ofstream& out, const char* name, const glm::mat4& m) {
  out << name;
  const float* v = glm::value_ptr(m);
  for (int i = 0; i < 16; ++i) out << ' ' << v[i];
  out << '\n';
}

void print_rect(std::ofstream& out, const char* name, const Viewport& v) {
  out << name << ' ' << v.x << ' ' << v.y << ' ' << v.width << ' ' << v.height << '\n';
}

}  // namespace

TrainerApp::TrainerApp(TrainerOptions options, std::string program_dir)
    : options_(std::move(options)), program_dir_(std::move(program_dir)) {
  settings_.wireframe = options_.wireframe;
}

TrainerApp::~TrainerApp() {
  if (session_) session_->stop();
  session_.reset();
  ui_.reset();
  renderer_.reset();
  window_.reset();
}

std::string TrainerApp::resolve_case(std::string& error) {
  std::string dir = options_.cases_dir;
  if (dir.empty()) {
    for (const std::string& candidate :
         {std::string(CATHBOX_CASES_DIR), program_dir_ + "/../../../cases", std::string("cases")}) {
      if (std::filesystem::is_directory(candidate)) {
        dir = candidate;
        break;
      }
    }
  }
  std::string scan_error;
  catalog_ = CaseCatalog::scan(dir, kCaseExtensions, scan_error);
  if (!options_.case_path.empty()) {
    const std::string name = std::filesystem::path(options_.case_path).filename().string();
    current_case_ = -1;
    for (std::size_t i = 0; i < catalog_.entries().size(); ++i) {
      if (catalog_.entries()[i].name == name) current_case_ = static_cast<int>(i);
    }
    return options_.case_path;
  }
  // The default: the single-wire neuro case with a target (the scripted hand reaches it), else
  // another neuro case file, else the neuro vessel file itself.
  current_case_ = -1;
  for (std::size_t i = 0; i < catalog_.entries().size(); ++i) {
    if (catalog_.entries()[i].name == kDefaultCase) current_case_ = static_cast<int>(i);
  }
  if (current_case_ < 0) current_case_ = catalog_.default_index(kPreferredCase, ".case");
  if (current_case_ < 0) {
    error = scan_error.empty() ? dir + ": no case files (.case, .hclm)" : scan_error;
    return {};
  }
  return catalog_.entries()[static_cast<std::size_t>(current_case_)].path;
}

bool TrainerApp::open_session(const std::string& case_path, bool scripted, std::string& error) {
  if (session_) session_->stop();
  session_.reset();
  SessionConfig config;
  config.case_path = case_path;
  config.box = scripted ? BoxChoice::kNone : options_.box;
  config.emu_socket = options_.emu_socket;
  config.scripted_hand = scripted;
  config.emu_program = program_dir_ + "/cathbox-emu";
  session_ = TrainerSession::open(config, error);
  return session_ != nullptr;
}

int TrainerApp::run() {
  if (options_.help) {
    std::fputs(trainer_usage(), stdout);
    return 0;
  }
  if (options_.headless && options_.frames == 0 && options_.bench_seconds <= 0.0) {
    return run_headless_summary();
  }
  return run_window();
}

int TrainerApp::run_headless_summary() {
  std::string error;
  const std::string case_path = resolve_case(error);
  if (case_path.empty() || !open_session(case_path, true, error)) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", error.c_str());
    return 2;
  }
  std::printf("cathbox-trainer: headless run of %s with the scripted hand (virtual time)\n",
              session_->case_name().c_str());
  const std::int64_t limit_ticks =
      options_.max_seconds > 0.0 ? static_cast<std::int64_t>(options_.max_seconds * 1000.0) : -1;
  LogEvent e;
  while (!session_->over() && (limit_ticks < 0 || session_->haptic_ticks() < limit_ticks)) {
    session_->step_virtual(100);
    while (session_->events().pop(e)) {
      std::printf("%8.3f s  %s\n", static_cast<double>(e.time_us) * 1e-6, e.text.data());
    }
  }
  session_->end_run();
  std::printf("end of run\n%s", RunMetrics::format(session_->summary()).c_str());
  return 0;
}

void TrainerApp::load_scene() {
  const vessel::SurfaceMesh& mesh = session_->vessel_mesh();
  const vessel::SurfaceMesh& overview = session_->overview_mesh();
  renderer_->set_vessel({mesh.positions_mm, mesh.normals, mesh.triangles},
                        {overview.positions_mm, overview.normals, overview.triangles});
  renderer_->set_target(session_->target_mm(), session_->target_radius_mm());
  frame_camera();
  ui_->add_line("case " + session_->case_name() + ": " + std::to_string(renderer_->detail_triangles()) +
                " triangles (global view " + std::to_string(renderer_->overview_triangles()) +
                "); hand: " + session_->device_status());
}

void TrainerApp::frame_camera() {
  const vessel::SurfaceMesh& mesh = session_->vessel_mesh();
  glm::vec3 lo(1e30F);
  glm::vec3 hi(-1e30F);
  for (const glm::vec3& p : mesh.positions_mm) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (mesh.positions_mm.empty()) lo = hi = glm::vec3(0.0F);
  camera_.frame(lo, hi);
}

void TrainerApp::handle_input(const ScreenLayout& layout) {
  GLFWwindow* w = window_->handle();
  if (!ui_->wants_mouse()) {
    double mx = 0.0;
    double my = 0.0;
    glfwGetCursorPos(w, &mx, &my);
    const auto dx = static_cast<float>(mx - last_mouse_x_);
    const auto dy = static_cast<float>(my - last_mouse_y_);
    last_mouse_x_ = mx;
    last_mouse_y_ = my;
    if (layout.global.contains(static_cast<float>(mx), static_cast<float>(my))) {
      camera_.zoom(ui_->mouse_wheel());
      // Double click on a vessel: orbit around that point from now on.
      const bool pressed = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
      if (pressed && !left_down_) {
        const double t = glfwGetTime();
        if (t - last_click_s_ < 0.35) {
          const glm::vec3 dir = camera_.ray_through(static_cast<float>(mx) - static_cast<float>(layout.global.x),
                                                    static_cast<float>(my) - static_cast<float>(layout.global.y),
                                                    static_cast<float>(layout.global.width),
                                                    static_cast<float>(layout.global.height));
          if (const auto hit = session_->pick(camera_.eye_mm(), dir)) camera_.target_mm = *hit;
        }
        last_click_s_ = t;
      }
      left_down_ = pressed;
      if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) camera_.orbit(dx, dy);
      if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
          glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS) {
        camera_.pan(dx, dy, static_cast<float>(layout.global.height));
      }
    }
  }
  double insert = 0.0;
  double twist = 0.0;
  if (!ui_->wants_keyboard()) {
    auto down = [&](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
    const double fast = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT) ? 4.0 : 1.0;
    if (down(GLFW_KEY_UP) || down(GLFW_KEY_W)) insert += 10.0 * fast;
    if (down(GLFW_KEY_DOWN) || down(GLFW_KEY_S)) insert -= 10.0 * fast;
    if (down(GLFW_KEY_LEFT) || down(GLFW_KEY_A)) twist += 1.5 * fast;
    if (down(GLFW_KEY_RIGHT) || down(GLFW_KEY_D)) twist -= 1.5 * fast;
    const bool tab = down(GLFW_KEY_TAB);
    if (tab && !tab_down_) session_->keyboard().request_tool_switch();
    tab_down_ = tab;
    const bool f = down(GLFW_KEY_F);
    if (f && !f_down_) settings_.wireframe = !settings_.wireframe;
    f_down_ = f;
    const bool c = down(GLFW_KEY_C);
    if (c && !c_down_) frame_camera();
    c_down_ = c;
    if (down(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(w, GLFW_TRUE);
  }
  session_->keyboard().set_speeds(insert, twist);
}

bool TrainerApp::write_screenshot(const ScreenLayout& layout, const SceneSnapshot& s, int fb_width,
                                  int fb_height) {
  const Image img = FrameCapture::read_back_buffer(fb_width, fb_height);
  std::string error;
  if (!PngWriter::write_file(options_.screenshot, img, error)) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", error.c_str());
    return false;
  }
  // The camera and what was drawn, so a test can project known points onto the image.
  std::ofstream out(options_.screenshot + ".txt");
  out << "size " << fb_width << ' ' << fb_height << '\n';
  out << "vessel_file " << session_->vessel_file() << '\n';
  print_rect(out, "global", layout.global);
  print_rect(out, "local", layout.local);
  print_rect(out, "hud", ui_->hud_rect());
  print_matrix(out, "view", camera_.view());
  print_matrix(out, "proj", camera_.projection(layout.global.aspect()));
  if (const auto t = session_->target_mm()) {
    out << "target " << t->x << ' ' << t->y << ' ' << t->z << ' ' << session_->target_radius_mm() << '\n';
  }
  for (int i = 0; i < s.tool_count; ++i) {
    for (const glm::vec3& p : s.tools[static_cast<std::size_t>(i)].nodes_mm) {
      out << "node " << i << ' ' << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
  }
  out << "tip " << s.tip_mm.x << ' ' << s.tip_mm.y << ' ' << s.tip_mm.z << '\n';
  out << "sim_time_us " << s.sim_time_us << '\n';
  return static_cast<bool>(out);
}

int TrainerApp::run_window() {
  std::string error;
  const std::string case_path = resolve_case(error);
  if (case_path.empty()) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", error.c_str());
    return 2;
  }
  window_ = GlWindow::create(options_.width, options_.height, "Cathbox trainer", !options_.headless, error);
  if (!window_) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", error.c_str());
    return 3;
  }
  const bool timed = options_.bench_seconds > 0.0;
  window_->set_vsync(!options_.headless && !timed);
  renderer_ = std::make_unique<SceneRenderer>();
  ui_ = std::make_unique<TrainerUi>();
  if (!renderer_->init(error) || !ui_->init(window_->handle())) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", error.empty() ? "cannot initialise the UI" : error.c_str());
    return 3;
  }
  // Headless or benchmarking, nobody is at the keyboard: the scripted hand drives the tool.
  const bool scripted = options_.headless || timed;
  if (!open_session(case_path, scripted, error)) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", error.c_str());
    return 2;
  }
  load_scene();
  std::printf("cathbox-trainer: %s, hand: %s\n", session_->case_name().c_str(),
              session_->device_status().c_str());
  std::fflush(stdout);
  const bool virtual_time = options_.frames > 0;
  if (!virtual_time) session_->start();
  // The software rasteriser's workers yield to the haptic thread (no effect on a GPU driver).
  (void)ThreadPriority::lower_threads_named("llvmpipe", 10);

  SteadyClock clock;
  const std::int64_t start_us = clock.now_us();
  FrameStats stats;
  std::int64_t last_us = clock.now_us();
  std::int64_t bench_start_us = -1;
  std::int64_t bench_start_ticks = 0;
  std::int64_t bench_start_process_cpu_us = 0;
  std::int64_t bench_start_render_cpu_us = 0;
  std::int64_t bench_start_haptic_cpu_us = 0;
  double fps = 0.0;
  int frame = 0;
  constexpr int kWarmupFrames = 20;
  // Without vsync (Xvfb, bench) frames are paced as a display would; headless frames are not.
  const std::int64_t frame_period_us =
      (options_.headless || timed) && options_.fps_cap > 0 && !virtual_time ? 1'000'000 / options_.fps_cap : 0;
  std::int64_t next_frame_us = clock.now_us();
  FrameStats work;
  while (!window_->should_close()) {
    if (frame_period_us > 0) {
      clock.sleep_until_us(next_frame_us);
      next_frame_us = std::max(next_frame_us + frame_period_us, clock.now_us());
    }
    const std::int64_t frame_start_us = clock.now_us();
    glfwPollEvents();
    if (virtual_time) session_->step_virtual(options_.sim_ms_per_frame);
    session_->snapshots().acquire();
    const SceneSnapshot& snap = session_->snapshots().read_slot();
    ui_->drain(session_->events());

    int fw = 0;
    int fh = 0;
    window_->framebuffer_size(fw, fh);
    const ScreenLayout layout = ScreenLayout::for_window(fw, fh);
    ui_->begin_frame();
    handle_input(layout);
    renderer_->clear(fw, fh);
    renderer_->update_tools(snap, settings_);
    renderer_->render_global(layout.global, fh, camera_.view(),
                             camera_.projection(layout.global.aspect()), settings_);
    renderer_->render_local(layout.local, fh, snap);
    const UiStatus status{fps, session_->device_status(), session_->case_name(),
                          session_->active_tool_name()};
    const UiActions act = ui_->draw(layout, snap, status, catalog_, current_case_, settings_);
    ui_->end_frame();
    ++frame;
    const bool last_frame = options_.frames > 0 && frame >= options_.frames;
    if (last_frame && !options_.screenshot.empty() && !write_screenshot(layout, snap, fw, fh)) return 1;
    window_->swap_buffers();

    const std::int64_t now = clock.now_us();
    const std::int64_t dt = now - last_us;
    last_us = now;
    fps = dt > 0 ? 0.9 * fps + 0.1 * 1e6 / static_cast<double>(dt) : fps;
    if (timed && frame == kWarmupFrames) {
      bench_start_us = now;
      bench_start_ticks = session_->haptic_ticks();
      bench_start_process_cpu_us = cpu_time_us(CLOCK_PROCESS_CPUTIME_ID);
      bench_start_render_cpu_us = cpu_time_us(CLOCK_THREAD_CPUTIME_ID);
      bench_start_haptic_cpu_us = session_->haptic_cpu_time_us();
    } else if (timed && frame > kWarmupFrames) {
      stats.add(dt);
      work.add(now - frame_start_us);
      if (static_cast<double>(now - bench_start_us) >= options_.bench_seconds * 1e6) break;
    }
    if (last_frame) break;
    if (!timed && options_.max_seconds > 0.0 &&
        static_cast<double>(now - start_us) >= options_.max_seconds * 1e6) {
      break;
    }

    if (act.end_run) session_->end_run();
    if (act.switch_tool) session_->keyboard().request_tool_switch();
    if (act.restart || act.pick_case >= 0) {
      const int pick = act.pick_case >= 0 ? act.pick_case : current_case_;
      const std::string path = pick >= 0 ? catalog_.entries()[static_cast<std::size_t>(pick)].path : case_path;
      if (open_session(path, scripted, error)) {
        current_case_ = pick;
        load_scene();
        session_->start();
      } else {
        ui_->add_line("cannot open " + path + ": " + error);
        if (!open_session(case_path, scripted, error)) return 2;
        load_scene();
        session_->start();
      }
    }
  }
  const std::int64_t end_us = clock.now_us();
  const std::int64_t end_ticks = session_->haptic_ticks();
  const std::int64_t end_process_cpu_us = cpu_time_us(CLOCK_PROCESS_CPUTIME_ID);
  const std::int64_t end_render_cpu_us = cpu_time_us(CLOCK_THREAD_CPUTIME_ID);
  const std::int64_t end_haptic_cpu_us = session_->haptic_cpu_time_us();
  session_->stop();
  if (timed) {
    const double seconds = static_cast<double>(end_us - bench_start_us) * 1e-6;
    std::printf("bench: %dx%d, %s: %zu triangles (global view %zu), renderer %s\n", options_.width,
                options_.height, session_->case_name().c_str(), renderer_->detail_triangles(),
                renderer_->overview_triangles(), reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    std::printf("frames: %zu in %.2f s (%s): %.1f fps, frame interval median %.2f ms, p99 %.2f ms\n",
                stats.count(), seconds,
                frame_period_us > 0 ? ("paced at " + std::to_string(options_.fps_cap) + " Hz").c_str() : "uncapped",
                stats.mean_fps(), stats.percentile_us(50) * 1e-3, stats.percentile_us(99) * 1e-3);
    std::printf("frame time (render work, poll to swap): median %.2f ms, p99 %.2f ms -> %.0f fps possible\n",
                work.percentile_us(50) * 1e-3, work.percentile_us(99) * 1e-3,
                work.percentile_us(50) > 0 ? 1e6 / work.percentile_us(50) : 0.0);
    // CPU time per frame is what the machine's load does not change: the render thread's own,
    // and the whole process's less the haptic thread's (so including Mesa's rasteriser threads).
    const double frames = static_cast<double>(std::max<std::size_t>(1, stats.count()));
    const double haptic_cpu_ms = static_cast<double>(end_haptic_cpu_us - bench_start_haptic_cpu_us) * 1e-3;
    std::printf("CPU per frame: render thread %.2f ms, all rendering threads %.2f ms; haptic thread %.1f %% of a core\n",
                static_cast<double>(end_render_cpu_us - bench_start_render_cpu_us) * 1e-3 / frames,
                (static_cast<double>(end_process_cpu_us - bench_start_process_cpu_us) * 1e-3 - haptic_cpu_ms) / frames,
                100.0 * haptic_cpu_ms / (seconds * 1e3));
    std::printf("triangles submitted per frame: global view %zu, local view %zu\n",
                renderer_->last_global_triangles(), renderer_->last_local_triangles());
    std::printf("haptic: %.1f Hz over the same window (%lld ticks, %lld dropped in the run), thread %s\n",
                static_cast<double>(end_ticks - bench_start_ticks) / seconds,
                static_cast<long long>(end_ticks - bench_start_ticks),
                static_cast<long long>(session_->snapshots().read_slot().dropped_ticks),
                session_->haptic_scheduling().c_str());
  } else if (!options_.headless) {
    std::printf("end of run\n%s", RunMetrics::format(session_->summary()).c_str());
  }
  return 0;
}

}  // namespace cathbox::app

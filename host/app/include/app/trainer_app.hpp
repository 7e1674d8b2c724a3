#pragma once
// cathbox-trainer's top level: picks the mode from the options (window, headless frames with a
// screenshot, headless run with the scripted hand, benchmark), owns the window, renderer, UI
// and the current TrainerSession, and runs the render loop.
#include <memory>
#include <string>

#include "app/case_catalog.hpp"
#include "app/orbit_camera.hpp"
#include "app/scene_renderer.hpp"
#include "app/screen_layout.hpp"
#include "app/trainer_options.hpp"
#include "app/trainer_session.hpp"

namespace cathbox::app {

class GlWindow;
class TrainerUi;

class TrainerApp {
 public:
  explicit TrainerApp(TrainerOptions options, std::string program_dir);
  ~TrainerApp();
  TrainerApp(const TrainerApp&) = delete;
  TrainerApp& operator=(const TrainerApp&) = delete;

  // Exit code: 0 success, 1 runtime failure, 2 bad case or options, 3 no display or no GL 3.3.
  [[nodiscard]] int run();

 private:
  [[nodiscard]] int run_headless_summary();
  [[nodiscard]] int run_window();
  [[nodiscard]] bool open_session(const std::string& case_path, bool scripted, std::string& error);
  void load_scene();
  void frame_camera();
  void handle_input(const ScreenLayout& layout);
  [[nodiscard]] bool write_screenshot(const ScreenLayout& layout, const SceneSnapshot& snapshot,
                                      int fb_width, int fb_height);
  [[nodiscard]] std::string resolve_case(std::string& error);

  TrainerOptions options_;
  std::string program_dir_;
  CaseCatalog catalog_;
  int current_case_ = -1;
  std::unique_ptr<TrainerSession> session_;
  std::unique_ptr<GlWindow> window_;
  std::unique_ptr<SceneRenderer> renderer_;
  std::unique_ptr<TrainerUi> ui_;
  OrbitCamera camera_;
  RenderSettings settings_;
  double last_mouse_x_ = 0.0;
  double last_mouse_y_ = 0.0;
  bool tab_down_ = false;
  bool left_down_ = false;
  double last_click_s_ = -1.0;
  bool f_down_ = false;
  bool c_down_ = false;
};

}  // namespace cathbox::app

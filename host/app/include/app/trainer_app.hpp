#pragma once
// cathbox-trainer's top level: picks the mode from the options (window, headless frames with a
// screenshot, headless run with the scripted hand, benchmark, Replay mode), owns the window,
// renderer and panels, and either a live session (host/session) or a replay player, and runs
// the render loop over whichever it has: the same views draw both.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "app/case_catalog.hpp"
#include "app/fluoro_frontend.hpp"
#include "app/carm_panel_model.hpp"
#include "app/device_drive.hpp"
#include "app/fluoro_vessel.hpp"
#include "app/input_controller.hpp"
#include "app/orbit_camera.hpp"
#include "app/scene_renderer.hpp"
#include "app/trainer_launch.hpp"
#include "app/trainer_options.hpp"
#include "app/vessel_follower.hpp"
#include "base/result.hpp"
#include "device/foot_pedal.hpp"
#include "session/fluoro_switches.hpp"
#include "session/keyboard_input.hpp"
#include "session/replay_player.hpp"
#include "session/session.hpp"

namespace cathbox::app {

class GlWindow;
class ServerLink;
class TrainerUi;
class ReplayPanel;
struct ReplayPanelActions;
struct UiActions;
struct CArmPanelActions;
struct UiStatus;
struct ScreenLayout;
class FluoroRenderer;

class TrainerApp {
 public:
  explicit TrainerApp(TrainerOptions options, std::string program_dir);
  ~TrainerApp();
  TrainerApp(const TrainerApp&) = delete;
  TrainerApp& operator=(const TrainerApp&) = delete;

  // Exit code (session/exit_codes.hpp): 0 success, 1 runtime failure, 2 bad case, record or
  // options, 6 no display or no OpenGL 3.3.
  [[nodiscard]] int run();

 private:
  [[nodiscard]] int run_headless_summary();
  [[nodiscard]] int run_headless_replay();
  [[nodiscard]] int run_window();
  // run_window's steps (trainer_app.cpp).
  struct FrameLoop;
  struct FrameActions;
  void start_window_run(FrameLoop& loop);
  [[nodiscard]] int run_frame(FrameLoop& loop, const std::string& chosen_path);
  [[nodiscard]] int draw_frame(FrameLoop& loop, session::Session& s, const session::SceneSnapshot& snap, FrameActions& actions);
  [[nodiscard]] bool time_frame(FrameLoop& loop, session::Session& s, std::int64_t frame_start_us);
  void finish_window_run(FrameLoop& loop);
  [[nodiscard]] int open_window(const std::string& case_path);
  [[nodiscard]] UiStatus ui_status(session::Session& s, const session::SceneSnapshot& snap, double fps) const;
  [[nodiscard]] CArmPanelActions draw_carm(const ScreenLayout& layout, const session::SceneSnapshot& snap, ScreenLayout& ui_layout);
  void render_main_view(const ScreenLayout& layout, int fh, const session::SceneSnapshot& snap);
  void post_live_actions(const UiActions& act, const InputActions& input, const CArmPanelActions& carm_act,
                         const session::SceneSnapshot& snap, std::int64_t now);
  [[nodiscard]] bool switch_run(const UiActions& act, const ReplayPanelActions& replay_act, const std::string& chosen_path,
                                bool virtual_time);
  [[nodiscard]] base::Status<> open_live(const std::string& case_path);
  [[nodiscard]] base::Status<> open_replay(const std::string& path);
  // Closes the live run (its record) and hands the record to the server link.
  void close_live(bool background_upload = true);
  // --server or the settings file: the link (exit code, or -1 to go on).
  [[nodiscard]] int open_server_link();
  // --pedal-gpio: the foot pedal opened (-1), else the exit code (bad option 2, no line 3).
  [[nodiscard]] int open_foot_pedal();
  // The case to open: the assigned one when joined to a server, else choose_case().
  [[nodiscard]] CaseChoice choose();
  [[nodiscard]] session::Session& current();
  void load_scene();
  // --view, else the case's `realistic`: the fluoroscopic main view, its C-arm pose.
  void load_fluoro_view(const session::SessionCase& scene);
  void frame_camera();
  // The views follow the session's wall (a balloon widened the lumen): uploads a prepared one.
  void follow_wall(const session::Session& s, std::uint64_t generation, double wall_pressure_kPa, bool wait);

  TrainerOptions options_;
  std::string program_dir_;
  CaseCatalog catalog_;
  int current_case_ = -1;
  std::string case_path_;
  bool scripted_ = false;  // nobody at the keyboard (headless, bench): the autopilot drives
  session::KeyboardInput keyboard_;
  std::unique_ptr<device::FootPedal> foot_pedal_;  // --pedal-gpio
  session::FluoroSwitches fluoro_switches_;
  DeviceDrive drive_;  // U / E: the stent's unsheathing and retrieval drives of the keyboard hand  // Space / I / R / X and the foot pedal into fluoroscopy controls
  std::unique_ptr<session::Session> live_;
  std::unique_ptr<ServerLink> link_;
  std::optional<std::int64_t> live_assignment_;
  std::string record_path_;
  std::unique_ptr<session::ReplayPlayer> replay_;
  std::unique_ptr<GlWindow> window_;
  std::unique_ptr<SceneRenderer> renderer_;
  std::unique_ptr<FluoroRenderer> fluoro_;  // --view fluoro: the main view
  SnapshotFluoroSettings fluoro_settings_;
  FluoroInputs fluoro_inputs_;  // the shown pulse's, kept until the next pulse
  CArmPanelModel carm_panel_;  // the C-arm panel's fields (with the case's working views)
  vessel::SurfaceMesh fluoro_mesh_;  // the case's surface at fluoro_surface_options() (else the collision surface is used)
  FluoroVessel fluoro_vessel_;  // that surface tied to the session's contrast cells
  std::string fluoro_error_;  // the last one shown in the output panel
  VesselFollower follower_;  // prepares a widened vessel off the render thread
  std::unique_ptr<VesselFollower::Prepared> shown_wall_;  // the widened vessel the views show
  std::unique_ptr<TrainerUi> ui_;
  std::unique_ptr<ReplayPanel> replay_panel_;
  InputController input_;
  OrbitCamera camera_;
  RenderSettings settings_;
};

}  // namespace cathbox::app

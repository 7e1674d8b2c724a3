#pragma once
// The trainer's Dear ImGui panels: the HUD over the global view (insertion, rotation, hand
// force, haptic rate, frame rate, device status, view toggles, the case picker's button), the
// case picker (case_picker_panel.hpp), the output panel
// (contacts, faults, device events), the end-of-run panel (end_of_run_panel.hpp) and, in Replay
// mode, the replay controls (replay_panel.hpp).
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "app/case_catalog.hpp"
#include "app/scene_renderer.hpp"
#include "app/screen_layout.hpp"
#include "session/event_log.hpp"
#include "session/scene_snapshot.hpp"

struct GLFWwindow;

namespace cathbox::app {

class CasePickerPanel;

struct UiStatus {
  double fps = 0.0;
  std::string device;      // e.g. "emulated box (socket /tmp/...)", "keyboard"
  std::string case_name;
  std::string tool_name;   // the active tool
  bool replay = false;     // Replay mode: no case picker, no driving
  std::string record;      // the record being written (live) or played (replay)
  bool can_detach = false;  // the held tool's coil is attached: the HUD names K
  bool detaching = false;   // its detachment zone is parting: the HUD asks for a still pusher
  bool can_load = false;    // its coil is released and a next one listed: the HUD names L
  // A thrombectomy case: the HUD names V (aspiration) and B (balloon guide) and their state.
  int aspiration = -1;      // -1: no aspiration catheter; 0 off; 1 on
  int balloon_guide = -1;   // -1: no balloon guide; 0 deflated; 1 inflated (flow arrest)
  std::vector<std::string> drive_hints;  // a stent retriever: the U and E keys' lines (DeviceDrive::hints)
};

struct UiActions {
  int pick_case = -1;     // index into the catalog
  bool open_picker = false;  // the HUD's "cases" button: the case picker opens
  bool restart = false;
  bool end_run = false;
  bool switch_tool = false;
  bool replay_this_run = false;  // the end-of-run panel's "replay"
};

class TrainerUi {
 public:
  TrainerUi();
  ~TrainerUi();
  TrainerUi(const TrainerUi&) = delete;
  TrainerUi& operator=(const TrainerUi&) = delete;

  // Installs the GLFW and OpenGL3 backends on the window (with its context current).
  [[nodiscard]] bool init(GLFWwindow* window);
  // Shows the case picker (case_picker_panel.hpp) from the next frame on.
  void open_picker();
  void begin_frame();
  // Draws every panel and returns what the trainee asked for.
  [[nodiscard]] UiActions draw(const ScreenLayout& layout, const session::SceneSnapshot& snapshot,
                               const UiStatus& status, const CaseCatalog& catalog,
                               int current_case, RenderSettings& settings);
  void end_frame();

  // Output panel lines (kept to the last few hundred).
  void add_line(std::string line);
  void drain(session::EventLog& log);
  [[nodiscard]] bool wants_mouse() const;
  [[nodiscard]] bool wants_keyboard() const;
  // Mouse wheel steps of this frame (the GLFW backend collects them).
  [[nodiscard]] float mouse_wheel() const;
  // Where the HUD was drawn last frame, for tests that must not sample under it.
  [[nodiscard]] const Viewport& hud_rect() const { return hud_rect_; }

 private:
  bool ready_ = false;
  std::deque<std::string> lines_;
  bool scroll_to_bottom_ = false;
  Viewport hud_rect_{};
  std::unique_ptr<CasePickerPanel> picker_;
};

}  // namespace cathbox::app

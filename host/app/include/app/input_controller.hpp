#pragma once
// Mouse and keyboard in the trainer's window, once per frame: orbit / pan / zoom the global
// view, double-click a vessel to orbit around it, F wireframe, C re-frame, Esc quit; and the
// keyboard hand: Up/Down (W/S) push and pull at 10 mm/s, Left/Right (A/D) twist at 1.5 rad/s,
// Shift x4, Tab takes the other tool; coils: K detaches the held coil tool's coil, L loads its
// next coil at the hub (after a detach; the case's next_coil lines); fluoroscopy: Space the pedal (held), I inject, R the
// roadmap, X clears it, [ / ] the C-arm 5 degrees towards RAO / LAO, - / = caudal / cranial
// (session::FluoroSwitches turns them into controls); a stent retriever: U unsheathes, E
// retrieves (DeviceDrive, device_drive.hpp).
#include <functional>
#include <optional>

#include <glm/vec3.hpp>

#include "app/orbit_camera.hpp"
#include "app/scene_renderer.hpp"
#include "app/screen_layout.hpp"
#include "session/fluoro_switches.hpp"
#include "session/keyboard_input.hpp"

struct GLFWwindow;

namespace cathbox::app {

class TrainerUi;

struct InputActions {
  bool switch_tool = false;
  bool frame_camera = false;
  bool detach_coil = false;  // K pressed
  bool load_coil = false;    // L pressed
  bool aspiration = false;     // V pressed: the aspiration catheter's vacuum on / off
  bool balloon_guide = false;  // B pressed: the balloon guide inflated / deflated
  bool unsheathe = false;      // U pressed: the stent's unsheathing drive (device_drive.hpp)
  bool retrieve = false;       // E pressed: its retrieval drive
  bool steering = false;       // an arrow or WASD key held (stops a drive)
  session::FluoroKeys fluoro;  // the fluoroscopy keys held now
};

class InputController {
 public:
  using Pick = std::function<std::optional<glm::vec3>(const glm::vec3& origin_mm, const glm::vec3& direction)>;

  // `keyboard` is null in Replay mode (nothing to drive).
  [[nodiscard]] InputActions handle(GLFWwindow* window, const TrainerUi& ui, const ScreenLayout& layout,
                                    OrbitCamera& camera, RenderSettings& settings, const Pick& pick,
                                    session::KeyboardInput* keyboard);

 private:
  void handle_mouse(GLFWwindow* w, const TrainerUi& ui, const ScreenLayout& layout, OrbitCamera& camera, const Pick& pick);
  void handle_keys(GLFWwindow* w, RenderSettings& settings, InputActions& act, double& insert, double& twist);

  double last_mouse_x_ = 0.0;
  double last_mouse_y_ = 0.0;
  bool tab_down_ = false;
  bool left_down_ = false;
  double last_click_s_ = -1.0;
  bool f_down_ = false;
  bool c_down_ = false;
  bool k_down_ = false;
  bool l_down_ = false;
  bool v_down_ = false;
  bool b_down_ = false;
  bool u_down_ = false;
  bool e_down_ = false;
};

}  // namespace cathbox::app

#include "app/input_controller.hpp"

#include "app/gl.hpp"
#include "app/trainer_ui.hpp"

namespace cathbox::app {

// The mouse over the 3D view: wheel zooms, left drag orbits (a double click on a vessel orbits
// around that point), right or middle drag pans.
void InputController::handle_mouse(GLFWwindow* w, const TrainerUi& ui, const ScreenLayout& layout, OrbitCamera& camera,
                                   const Pick& pick) {
  double mx = 0.0;
  double my = 0.0;
  glfwGetCursorPos(w, &mx, &my);
  const auto dx = static_cast<float>(mx - last_mouse_x_);
  const auto dy = static_cast<float>(my - last_mouse_y_);
  last_mouse_x_ = mx;
  last_mouse_y_ = my;
  if (layout.global.contains(static_cast<float>(mx), static_cast<float>(my))) {
    camera.zoom(ui.mouse_wheel());
    // Double click on a vessel: orbit around that point from now on.
    const bool pressed = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (pressed && !left_down_) {
      const double t = glfwGetTime();
      if (t - last_click_s_ < 0.35) {
        const glm::vec3 dir = camera.ray_through(static_cast<float>(mx) - static_cast<float>(layout.global.x),
                                                 static_cast<float>(my) - static_cast<float>(layout.global.y),
                                                 static_cast<float>(layout.global.width),
                                                 static_cast<float>(layout.global.height));
        if (const auto hit = pick(camera.eye_mm(), dir)) camera.target_mm = *hit;
      }
      last_click_s_ = t;
    }
    left_down_ = pressed;
    if (pressed) camera.orbit(dx, dy);
    if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
        glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS) {
      camera.pan(dx, dy, static_cast<float>(layout.global.height));
    }
  }
}

// The keys: arrows or WASD drive the hand (`insert`, `twist`; shift is faster), one press each
// for the actions, Escape closes the window.
void InputController::handle_keys(GLFWwindow* w, RenderSettings& settings, InputActions& act, double& insert, double& twist) {
  auto down = [&](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
  const double fast = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT) ? 4.0 : 1.0;
  const bool push = down(GLFW_KEY_UP) || down(GLFW_KEY_W);
  const bool pull = down(GLFW_KEY_DOWN) || down(GLFW_KEY_S);
  const bool left = down(GLFW_KEY_LEFT) || down(GLFW_KEY_A);
  const bool right = down(GLFW_KEY_RIGHT) || down(GLFW_KEY_D);
  insert += (push ? 10.0 : 0.0) - (pull ? 10.0 : 0.0);
  twist += (left ? 1.5 : 0.0) - (right ? 1.5 : 0.0);
  insert *= fast;
  twist *= fast;
  act.steering = push || pull || left || right;  // stops a U / E drive
  // A key's press, once (not while it is held).
  auto pressed = [&](int key, bool& was_down) {
    const bool now = down(key);
    const bool edge = now && !was_down;
    was_down = now;
    return edge;
  };
  act.switch_tool = pressed(GLFW_KEY_TAB, tab_down_);
  if (pressed(GLFW_KEY_F, f_down_)) settings.wireframe = !settings.wireframe;
  act.frame_camera = pressed(GLFW_KEY_C, c_down_);
  act.detach_coil = pressed(GLFW_KEY_K, k_down_);
  act.load_coil = pressed(GLFW_KEY_L, l_down_);
  act.aspiration = pressed(GLFW_KEY_V, v_down_);
  act.balloon_guide = pressed(GLFW_KEY_B, b_down_);
  act.unsheathe = pressed(GLFW_KEY_U, u_down_);
  act.retrieve = pressed(GLFW_KEY_E, e_down_);
  act.fluoro = {down(GLFW_KEY_SPACE), down(GLFW_KEY_I),           down(GLFW_KEY_R),     down(GLFW_KEY_X),
                down(GLFW_KEY_LEFT_BRACKET), down(GLFW_KEY_RIGHT_BRACKET), down(GLFW_KEY_MINUS), down(GLFW_KEY_EQUAL)};
  if (down(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(w, GLFW_TRUE);
}

InputActions InputController::handle(GLFWwindow* w, const TrainerUi& ui, const ScreenLayout& layout,
                                     OrbitCamera& camera, RenderSettings& settings, const Pick& pick,
                                     session::KeyboardInput* keyboard) {
  InputActions act;
  if (!ui.wants_mouse()) handle_mouse(w, ui, layout, camera, pick);
  double insert = 0.0;
  double twist = 0.0;
  if (!ui.wants_keyboard()) handle_keys(w, settings, act, insert, twist);
  if (keyboard != nullptr) keyboard->set_speeds(insert, twist);
  return act;
}

}  // namespace cathbox::app

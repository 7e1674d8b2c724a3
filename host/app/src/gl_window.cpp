#include "app/gl_window.hpp"

#include "app/gl.hpp"

namespace cathbox::app {
namespace {
std::string g_glfw_error;
int g_windows = 0;  // GLFW stays initialised while a window lives (several offscreen views at once)
void on_glfw_error(int code, const char* text) {
  g_glfw_error = "glfw error " + std::to_string(code) + ": " + (text ? text : "?");
}
}  // namespace

base::Result<std::unique_ptr<GlWindow>> GlWindow::create(int width, int height, const char* title, bool visible) {
  glfwSetErrorCallback(on_glfw_error);
  if (glfwInit() != GLFW_TRUE) {
    return base::Error{g_glfw_error.empty() ? "glfw: cannot initialise (no display?)" : g_glfw_error};
  }
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_SAMPLES, 0);
  GLFWwindow* w = glfwCreateWindow(width, height, title, nullptr, nullptr);
  if (w == nullptr) {
    if (g_windows == 0) glfwTerminate();
    return base::Error{g_glfw_error.empty() ? "glfw: cannot create an OpenGL 3.3 core window" : g_glfw_error};
  }
  glfwMakeContextCurrent(w);
  ++g_windows;
  return std::unique_ptr<GlWindow>(new GlWindow(w));
}

GlWindow::~GlWindow() {
  glfwDestroyWindow(window_);
  if (--g_windows == 0) glfwTerminate();
}

bool GlWindow::should_close() const { return glfwWindowShouldClose(window_) == GLFW_TRUE; }
void GlWindow::swap_buffers() { glfwSwapBuffers(window_); }
void GlWindow::set_vsync(bool on) { glfwSwapInterval(on ? 1 : 0); }
void GlWindow::framebuffer_size(int& width, int& height) const {
  glfwGetFramebufferSize(window_, &width, &height);
}

}  // namespace cathbox::app

#pragma once
// A GLFW window with an OpenGL 3.3 core context, visible or hidden (headless runs under Xvfb).
// Several may live at once (offscreen views); GLFW is terminated with the last one.
#include <memory>
#include <string>

#include "base/result.hpp"

struct GLFWwindow;

namespace cathbox::app {

class GlWindow {
 public:
  // Or one line when there is no display or no GL 3.3 context.
  [[nodiscard]] static base::Result<std::unique_ptr<GlWindow>> create(int width, int height, const char* title,
                                                                      bool visible);
  ~GlWindow();
  GlWindow(const GlWindow&) = delete;
  GlWindow& operator=(const GlWindow&) = delete;

  [[nodiscard]] GLFWwindow* handle() const { return window_; }
  [[nodiscard]] bool should_close() const;
  void swap_buffers();
  void set_vsync(bool on);
  // Framebuffer size in pixels.
  void framebuffer_size(int& width, int& height) const;

 private:
  explicit GlWindow(GLFWwindow* window) : window_(window) {}
  GLFWwindow* window_;
};

}  // namespace cathbox::app

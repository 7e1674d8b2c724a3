#pragma once
// The trainer's --screenshot: the back buffer as PNG, and beside it OUT.png.txt with what a
// test needs to project known points onto the image (viewports, the HUD's rectangle, the view
// and projection matrices, the target, the tools' nodes, the tip, the vessel file).
#include <optional>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "app/screen_layout.hpp"
#include "base/result.hpp"
#include "session/scene_snapshot.hpp"

namespace cathbox::app {

struct ScreenshotScene {
  const ScreenLayout& layout;
  const Viewport& hud;
  glm::mat4 view;
  glm::mat4 projection;
  std::string vessel_file;
  std::optional<glm::vec3> target_mm;
  float target_radius_mm = 0.0F;
};

// Or one line saying what failed.
[[nodiscard]] base::Status<> write_screenshot(const std::string& path, const ScreenshotScene& scene,
                                              const session::SceneSnapshot& snapshot, int fb_width, int fb_height);

}  // namespace cathbox::app

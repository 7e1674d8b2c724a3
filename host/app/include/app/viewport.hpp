#pragma once
// A rectangle of the window in pixels, origin at the top left (as in screenshots and ImGui).
namespace cathbox::app {

struct Viewport {
  int x = 0;
  int y = 0;
  int width = 1;
  int height = 1;
  [[nodiscard]] float aspect() const {
    return height > 0 ? static_cast<float>(width) / static_cast<float>(height) : 1.0F;
  }
  [[nodiscard]] bool contains(float px, float py) const {
    return px >= static_cast<float>(x) && py >= static_cast<float>(y) &&
           px < static_cast<float>(x + width) && py < static_cast<float>(y + height);
  }
};

}  // namespace cathbox::app

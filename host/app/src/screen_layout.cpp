#include "app/screen_layout.hpp"

#include <algorithm>

namespace cathbox::app {

ScreenLayout ScreenLayout::for_window(int width, int height) {
  width = std::max(width, 2);
  height = std::max(height, 2);
  // The right column holds a 4:3 local view of half the height, and is at most 40 % wide.
  const int right = std::clamp(height / 2 * 4 / 3, 1, width * 2 / 5);
  const int left = width - right;
  const int local_h = std::max(1, height / 2);
  ScreenLayout l;
  l.global = {0, 0, left, height};
  l.local = {left, 0, right, local_h};
  l.output = {left, local_h, right, height - local_h};
  return l;
}

}  // namespace cathbox::app

#pragma once
// The seed's three areas (5.3): the global view on the left, the local (endoluminal) view at
// the upper right, the output panel at the lower right.
#include "app/viewport.hpp"

namespace cathbox::app {

struct ScreenLayout {
  Viewport global;
  Viewport local;
  Viewport output;

  [[nodiscard]] static ScreenLayout for_window(int width, int height);
};

}  // namespace cathbox::app

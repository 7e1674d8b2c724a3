#pragma once
// Reads the rendered back buffer (before the swap) into an RGB image, top row first.
#include "app/png_writer.hpp"

namespace cathbox::app {

struct FrameCapture {
  [[nodiscard]] static Image read_back_buffer(int width, int height);
};

}  // namespace cathbox::app

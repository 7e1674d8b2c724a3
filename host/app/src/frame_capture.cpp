#include "app/frame_capture.hpp"

#include <cstring>

#include "app/gl.hpp"

namespace cathbox::app {

Image FrameCapture::read_back_buffer(int width, int height) {
  Image img;
  img.width = width;
  img.height = height;
  img.channels = 3;
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  std::vector<std::uint8_t> gl_rows(row * static_cast<std::size_t>(height));
  glFinish();
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, gl_rows.data());
  img.pixels.resize(gl_rows.size());
  for (int y = 0; y < height; ++y) {  // GL rows start at the bottom
    std::memcpy(img.pixels.data() + row * static_cast<std::size_t>(y),
                gl_rows.data() + row * static_cast<std::size_t>(height - 1 - y), row);
  }
  return img;
}

}  // namespace cathbox::app

#pragma once
// The PNG encoder for screenshots: 8-bit RGB or RGBA, through libpng.
#include <cstdint>
#include <string>
#include <vector>

#include "base/result.hpp"

namespace cathbox::app {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 3;                 // 3 = RGB, 4 = RGBA
  std::vector<std::uint8_t> pixels; // row-major, top row first, width * height * channels

  [[nodiscard]] const std::uint8_t* pixel(int x, int y) const {
    return pixels.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                            static_cast<std::size_t>(x)) * static_cast<std::size_t>(channels);
  }
};

class PngWriter {
 public:
  // The whole PNG file as bytes; empty when the image is malformed (size, channels, pixel count).
  [[nodiscard]] static std::vector<std::uint8_t> encode(const Image& image);
  // Writes the file; or one line saying what failed.
  [[nodiscard]] static base::Status<> write_file(const std::string& path, const Image& image);
};

}  // namespace cathbox::app

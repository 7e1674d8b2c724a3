#include "png_reader.hpp"

#include <png.h>

#include <fstream>
#include <iterator>

namespace cathbox::app::testing {

std::optional<Image> decode_png(const std::vector<std::uint8_t>& bytes, std::string& error) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()) == 0) {
    error = png.message;
    png_image_free(&png);
    return std::nullopt;
  }
  const bool alpha = (png.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  if ((png.format & PNG_FORMAT_FLAG_COLOR) == 0 || (png.format & PNG_FORMAT_FLAG_LINEAR) != 0) {
    error = "unsupported format (not 8-bit RGB or RGBA)";
    png_image_free(&png);
    return std::nullopt;
  }
  png.format = alpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  Image img;
  img.width = static_cast<int>(png.width);
  img.height = static_cast<int>(png.height);
  img.channels = alpha ? 4 : 3;
  img.pixels.resize(PNG_IMAGE_SIZE(png));
  if (png_image_finish_read(&png, nullptr, img.pixels.data(), 0, nullptr) == 0) {
    error = png.message;
    png_image_free(&png);
    return std::nullopt;
  }
  return img;
}

std::optional<Image> read_png(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open";
    return std::nullopt;
  }
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return decode_png(bytes, error);
}

}  // namespace cathbox::app::testing

#include "app/png_writer.hpp"

#include <png.h>

#include <fstream>

namespace cathbox::app {

std::vector<std::uint8_t> PngWriter::encode(const Image& image) {
  if (image.width <= 0 || image.height <= 0 || (image.channels != 3 && image.channels != 4) ||
      image.width > (1 << 16) || image.height > (1 << 16)) {
    return {};
  }
  const std::size_t row_bytes =
      static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.channels);
  if (image.pixels.size() != row_bytes * static_cast<std::size_t>(image.height)) return {};

  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = image.channels == 4 ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  const auto stride = static_cast<png_int_32>(row_bytes);
  png_alloc_size_t size = 0;
  // First call sizes the file, second writes it.
  if (png_image_write_to_memory(&png, nullptr, &size, 0, image.pixels.data(), stride, nullptr) == 0) {
    png_image_free(&png);
    return {};
  }
  std::vector<std::uint8_t> out(size);
  if (png_image_write_to_memory(&png, out.data(), &size, 0, image.pixels.data(), stride, nullptr) == 0) {
    png_image_free(&png);
    return {};
  }
  out.resize(size);
  return out;
}

base::Status<> PngWriter::write_file(const std::string& path, const Image& image) {
  const std::vector<std::uint8_t> png = encode(image);
  if (png.empty()) {
    return base::Error{"png: invalid image " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                       "x" + std::to_string(image.channels)};
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) return base::Error{path + ": cannot open for writing"};
  out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  if (!out) return base::Error{path + ": write failed"};
  return base::Ok{};
}

}  // namespace cathbox::app

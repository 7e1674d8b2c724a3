#pragma once
// Test helper: decodes the PNGs the trainer writes (8-bit RGB/RGBA, stored deflate blocks,
// filter 0), checking every CRC, the zlib header and the Adler-32. Anything else is refused.
#include <optional>
#include <string>
#include <vector>

#include "app/png_writer.hpp"

namespace cathbox::app::testing {

[[nodiscard]] std::optional<Image> decode_png(const std::vector<std::uint8_t>& bytes,
                                              std::string& error);
[[nodiscard]] std::optional<Image> read_png(const std::string& path, std::string& error);

}  // namespace cathbox::app::testing

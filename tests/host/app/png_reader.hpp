#pragma once
// Test helper: decodes the PNGs the trainer writes through libpng (checks every CRC and the
// zlib stream); 8-bit RGB or RGBA comes back as it was written, anything else is refused.
#include <optional>
#include <string>
#include <vector>

#include "app/png_writer.hpp"

namespace cathbox::app::testing {

[[nodiscard]] std::optional<Image> decode_png(const std::vector<std::uint8_t>& bytes,
                                              std::string& error);
[[nodiscard]] std::optional<Image> read_png(const std::string& path, std::string& error);

}  // namespace cathbox::app::testing

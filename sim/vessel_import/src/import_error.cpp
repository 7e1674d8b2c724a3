#include "vessel_import/import_error.hpp"

#include <algorithm>
#include <string_view>

namespace cathbox::vessel_import {

std::string ImportError::to_string() const {
  if (line > 0) return file + ":" + std::to_string(line) + ": " + message;
  if (byte > 0) return file + ":byte " + std::to_string(byte) + ": " + message;
  return file + ": " + message;
}

int line_of(std::string_view text, std::size_t at) {
  at = std::min(at, text.size());
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

}  // namespace cathbox::vessel_import

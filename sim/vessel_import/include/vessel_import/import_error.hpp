#pragma once
// One problem in an imported file, located by line or byte: "tree.swc:12: parent 40 is not
// defined", "aorta.mrk.json:88: ...", "cl.vtp:byte 5123: ...", or just "cl.vtk: ..." when the
// reader gives no position.
#include <cstddef>
#include <string>

namespace cathbox::vessel_import {

struct ImportError {
  std::string file;
  int line = 0;           // 1-based, 0 when unknown
  std::size_t byte = 0;   // 1-based byte offset, 0 when unknown (used when there is no line)
  std::string message;

  [[nodiscard]] std::string to_string() const;
};

// The 1-based line of the 0-based byte offset `at` in `text` (clamped to the text).
[[nodiscard]] int line_of(std::string_view text, std::size_t at);

}  // namespace cathbox::vessel_import

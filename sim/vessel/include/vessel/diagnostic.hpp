#pragma once
// One problem found in an input, located by file and line ("neuro.hclm:12: radius must be > 0").
#include <string>

namespace cathbox::vessel {

struct Diagnostic {
  std::string file;  // file name as given by the caller ("<text>" for in-memory input)
  int line = 0;      // 1-based line number; 0 when the problem is not tied to one line
  std::string message;

  // "file:line: message" (or "file: message" when line is 0).
  [[nodiscard]] std::string to_string() const;
};

}  // namespace cathbox::vessel

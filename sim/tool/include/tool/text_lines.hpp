#pragma once
// Line and word splitting shared by the case and script parsers: comments (#), blank lines,
// CRLF and tabs are tolerated; numbers must be finite.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::tool {

class TextLines {
 public:
  explicit TextLines(std::string_view text) : text_(text) {}
  // Next non-blank line split into words; false at the end.
  bool next(std::vector<std::string_view>& words);
  [[nodiscard]] std::size_t line() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

[[nodiscard]] std::optional<double> parse_number(std::string_view word);
// "file:line: message"
[[nodiscard]] std::string located(std::string_view file, std::size_t line, std::string_view message);
// Reads a whole file; empty optional when it cannot be read.
[[nodiscard]] std::optional<std::string> read_text_file(const std::string& path, std::size_t max_bytes);

}  // namespace cathbox::tool

#pragma once
// Line by line over a text file's words, as the case and script parsers read: comments (#),
// blank lines, CRLF and tabs are tolerated; "file:line: message" for errors.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/text_tokens.hpp"

namespace cathbox::base::text {

class TextLines {
 public:
  explicit TextLines(std::string_view text) : text_(text) {}
  // Next line with a word (before any '#') split into words; false at the end.
  bool next(std::vector<std::string_view>& words) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      line = line.substr(0, line.find('#'));
      split_tokens(line, words);
      if (!words.empty()) return true;
    }
    return false;
  }
  [[nodiscard]] std::size_t line() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

// "file:line: message"
[[nodiscard]] inline std::string located(std::string_view file, std::size_t line, std::string_view message) {
  std::string out(file);
  out += ':';
  out += std::to_string(line);
  out += ": ";
  out += message;
  return out;
}

}  // namespace cathbox::base::text

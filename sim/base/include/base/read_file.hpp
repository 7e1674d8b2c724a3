#pragma once
// The bytes of a file no larger than a limit, read in one go: the one reader behind the case's
// own files (host/session's case and vessel texts, sim/scenario's case surface). The caller
// words the line (its files' names differ), so the error says only which way it failed.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "base/result.hpp"

namespace cathbox::base {

struct ReadFileError {
  enum class Kind { kCannotOpen, kTooLarge } kind = Kind::kCannotOpen;
  std::uintmax_t size_bytes = 0;  // kTooLarge: the file's size
};

// The whole of `path` when it opens and holds at most `limit_bytes`; the size is checked before
// anything is read, so a huge file costs nothing.
[[nodiscard]] inline Result<std::string, ReadFileError> read_file(const std::string& path, std::uintmax_t limit_bytes) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return ReadFileError{ReadFileError::Kind::kCannotOpen, 0};
  if (size > limit_bytes) return ReadFileError{ReadFileError::Kind::kTooLarge, size};
  std::ifstream in(path, std::ios::binary);
  if (!in) return ReadFileError{ReadFileError::Kind::kCannotOpen, 0};
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace cathbox::base

#pragma once
// The user's folders of cathbox (the XDG base directory rules) and where runs are recorded.
#include <cstdint>
#include <string>

#include "base/result.hpp"

namespace cathbox::session {

enum class UserDir {
  kData,    // $XDG_DATA_HOME, else ~/.local/share
  kCache,   // $XDG_CACHE_HOME, else ~/.cache
  kConfig,  // $XDG_CONFIG_HOME, else ~/.config
};
// <base>/cathbox/<relative>; the variable counts only when absolute; no HOME: "./.local/share"...
[[nodiscard]] std::string user_dir(UserDir kind, const std::string& relative);

// Where runs are recorded: user_dir(kData, "records").
[[nodiscard]] std::string records_dir();
// A new record's path in `dir`: YYYYMMDD-HHMMSS-<case>.cbxrec (local time; the case name
// reduced to letters, digits, '-' and '_'; "-2", "-3", ... when taken). Creates `dir`;
// one line when it cannot.
[[nodiscard]] base::Result<std::string> new_record_path(const std::string& dir, const std::string& case_name);

}  // namespace cathbox::session

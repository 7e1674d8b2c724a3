#pragma once
// Where runs are recorded: $XDG_DATA_HOME/cathbox/records/, or ~/.local/share/cathbox/records/
// when XDG_DATA_HOME is unset or not absolute (the XDG base directory rules).
#include <cstdint>
#include <string>

namespace cathbox::session {

[[nodiscard]] std::string records_dir();
// A new record's path in `dir`: YYYYMMDD-HHMMSS-<case>.cbxrec (local time; the case name
// reduced to letters, digits, '-' and '_'; "-2", "-3", ... when taken). Creates `dir`;
// empty with one line in `error` when it cannot.
[[nodiscard]] std::string new_record_path(const std::string& dir, const std::string& case_name, std::string& error);

}  // namespace cathbox::session

#pragma once
// Time-stamped actions for the headless scenario runner (documented in sim/tool/README.md):
//
//   # time_ms  verb       arguments
//   0          select     guidewire          # the tool the next actions move (by name)
//   0          insert_to  120 at 20          # mm, optional speed in mm/s (default 20)
//   1500       rotate_by  90 at 180          # degrees, optional speed in deg/s (default 180)
//   4000       insert_by  -5
//   6000       end                           # optional: stop here
//
// Times are milliseconds of virtual time, non-decreasing. A motion moves the value towards
// its target at the given speed; a new motion of the same tool and axis replaces the old one.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::tool {

enum class ActionKind : std::uint8_t { kSelect, kInsertTo, kInsertBy, kRotateTo, kRotateBy, kEnd };

struct Action {
  std::int64_t time_ms = 0;
  ActionKind kind = ActionKind::kEnd;
  double value = 0.0;   // mm or degrees
  double speed = 0.0;   // mm/s or deg/s
  std::string tool;     // kSelect
  std::size_t line = 0; // source line, for errors found later
};

struct Script {
  std::vector<Action> actions;
};

struct ScriptParse {
  std::optional<Script> value;
  std::string error;  // "file:line: message" when value is empty
};

[[nodiscard]] ScriptParse parse_script(std::string_view text, std::string_view file_name);
[[nodiscard]] ScriptParse load_script(const std::string& path);

inline constexpr double kDefaultInsertSpeed_mm_s = 20.0;
inline constexpr double kDefaultRotateSpeed_deg_s = 180.0;

}  // namespace cathbox::tool

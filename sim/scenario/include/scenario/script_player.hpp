#pragma once
// Plays an action script (action_script.hpp) one millisecond at a time: which tool is selected,
// and where each tool's insertion and rotation are after each step. The headless scenario runner
// (`cathbox sim run`) and the session's action-script hand (`cathbox session run --script`) both
// move their tools with it, so a script means the same thing to both.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/result.hpp"
#include "scenario/action_script.hpp"

namespace cathbox::tool {

struct ToolSpec;

class ScriptPlayer {
 public:
  struct ToolInfo {
    std::string name;
    double max_insertion_mm = 0.0;
    bool coil = false;     // carries a detachable coil (a `detach` may select it)
    bool balloon = false;  // carries a balloon (inflate / deflate may act on it)
    // Coil tools: the largest insertion with each next coil loaded (`load_coil`), in order.
    std::vector<double> next_coil_max_insertion_mm{};
    bool aspirator = false;  // the case's `aspiration` names it (aspiration on / off may act on it)
  };

  // Checks that every tool the script selects exists, that every `detach` finds a coil, every
  // inflate / deflate and `balloon_guide` a balloon and every `aspiration` a vacuum source on the
  // tool selected then; on failure returns one line: "file:line: select: the case has no tool 'x' (tools: a b)",
  // "file:line: detach: 'x' carries no coil", "file:line: inflate: tool 'x' has no balloon" or
  // "file:line: aspiration: tool 'x' has no vacuum source (the case's `aspiration` names the catheter that has)";
  // and that every `load_coil` finds a next coil on the selected tool and comes after a
  // `detach` of its present coil ("file:line: load_coil: 'x' has no further coil (the case
  // lists 1 after the first)", "file:line: load_coil: the coil of 'x' is not detached yet").
  [[nodiscard]] static base::Result<ScriptPlayer> make(const Script& script, std::span<const ToolInfo> tools,
                                                       std::size_t selected, const std::string& script_name);

  // A balloon action due at this step, on the tool selected when it came.
  struct DeviceAction {
    ActionKind kind = ActionKind::kDeflate;
    double value = 0.0;
    std::size_t tool = 0;
    std::size_t line = 0;
  };
  static constexpr std::size_t kMaxDeviceActions = 4;  // per millisecond; later ones wait a step
  struct Step {
    std::optional<std::size_t> selected;  // a `select` took effect at this step
    bool ended = false;                   // an `end` action is due: stop before stepping
    std::span<const Action> due;          // the actions applied at this step, in order (the
                                          // imaging verbs are its owner's to act on)
    std::optional<std::size_t> detach;    // a `detach` of this tool's coil is due
    std::size_t detach_line = 0;          // ... from this script line
    std::optional<std::size_t> load_coil; // a `load_coil` of this tool is due (its insertion and
                                          // rotation here are 0 from this step on)
    std::size_t load_coil_line = 0;
    std::array<DeviceAction, kMaxDeviceActions> devices{};
    std::size_t device_count = 0;
    // Thrombectomy actions due at this step (aspiration, balloon_guide; value 1 on, 0 off), on
    // the tool selected when each came: the session's controls.
    std::array<DeviceAction, kMaxDeviceActions> clot_devices{};
    std::size_t clot_device_count = 0;
  };
  // Applies the actions due at `now_ms` (0, 1, 2, ... in turn), then, unless the script ended,
  // moves every running motion by one millisecond.
  Step advance(std::int64_t now_ms);

  [[nodiscard]] double insertion_mm(std::size_t tool) const { return insertion_[tool]; }
  [[nodiscard]] double rotation_rad(std::size_t tool) const { return rotation_[tool]; }
  [[nodiscard]] std::size_t selected() const { return selected_; }
  // Called once after each step that advance(now_ms) moved: true once every action is done
  // and no motion has run for `settle_ms` (never for a script with `end`, which stops there).
  [[nodiscard]] bool settled(std::int64_t now_ms, std::int64_t settle_ms);

 private:
  struct Motion {
    bool active = false;
    double target = 0.0;
    double speed_per_ms = 0.0;
  };
  ScriptPlayer(const Script& script, std::span<const ToolInfo> tools, std::size_t selected);

  std::vector<Action> actions_;
  std::vector<std::string> names_;
  std::vector<double> max_insertion_mm_;
  std::vector<std::vector<double>> next_max_insertion_mm_;  // per tool, per next coil
  std::vector<std::size_t> loaded_;                         // next coils loaded per tool
  std::vector<Motion> insert_, rotate_;
  std::vector<double> insertion_, rotation_;
  std::size_t next_ = 0;
  std::size_t selected_ = 0;
  std::int64_t last_action_ms_ = 0;
  std::int64_t idle_since_ms_ = -1;
  bool has_end_ = false;
  bool moving_ = false;
};

// What a player needs to know of a tool.
[[nodiscard]] ScriptPlayer::ToolInfo tool_info(const ToolSpec& spec);

}  // namespace cathbox::tool

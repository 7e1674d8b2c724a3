#pragma once
// An action script (*.actions, sim/scenario/action_script.hpp) as the hand: the same parser and the
// same player (tool::ScriptPlayer) as `cathbox sim run`, one millisecond per tick. `select`
// becomes a select control (recorded like a trainee's), the imaging verbs (`fluoro`, `inject`,
// `carm`, `roadmap`) the fluoroscopy unit's controls (fluoro_controls.hpp); the motions move
// every tool. The
// hand finishes at `end`, or 100 ms after the last motion ended.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/result.hpp"
#include "session/hand.hpp"
#include "session/session_case.hpp"
#include "scenario/action_script.hpp"
#include "scenario/script_player.hpp"

namespace cathbox::session {

class ActionScriptHand final : public Hand {
 public:
  // Loads and checks the script against the case's tools; null with "file:line: message".
  [[nodiscard]] static base::Result<std::unique_ptr<ActionScriptHand>> load(
      const std::string& path, const std::vector<tool::ScriptPlayer::ToolInfo>& tools, std::size_t held);
  // The script against a loaded case (its tools and their insertion limits; the first tool held).
  [[nodiscard]] static base::Result<std::unique_ptr<ActionScriptHand>> load(const std::string& path,
                                                                            const SessionCase& scene);
  [[nodiscard]] static std::vector<tool::ScriptPlayer::ToolInfo> tool_infos(const SessionCase& scene);
  [[nodiscard]] static base::Result<std::unique_ptr<ActionScriptHand>> make(
      const tool::Script& script, const std::string& name, const std::vector<tool::ScriptPlayer::ToolInfo>& tools,
      std::size_t held);

  [[nodiscard]] HandKind kind() const override { return HandKind::kActionScript; }
  [[nodiscard]] std::string describe() const override { return "action script " + name_; }
  void controls(std::int64_t tick, ControlSink& sink) override;
  void read(std::int64_t tick, TickInput& input) override;
  [[nodiscard]] bool finished() const override { return finished_; }
  [[nodiscard]] std::string finish_reason() const override;

 private:
  ActionScriptHand(tool::ScriptPlayer player, std::string name) : player_(std::move(player)), name_(std::move(name)) {}

  tool::ScriptPlayer player_;
  std::string name_;
  bool ended_ = false;   // an `end` action
  bool finished_ = false;
};

}  // namespace cathbox::session

#include "session/action_script_hand.hpp"

#include <algorithm>
#include <cmath>

#include "session/control.hpp"
#include "session/fluoro_controls.hpp"
#include "tool/rod.hpp"

namespace cathbox::session {
namespace {
constexpr std::int64_t kSettle_ms = 100;  // as `cathbox sim run` (tool::ScenarioOptions)
}  // namespace

base::Result<std::unique_ptr<ActionScriptHand>> ActionScriptHand::load(
    const std::string& path, const std::vector<tool::ScriptPlayer::ToolInfo>& tools, std::size_t held) {
  tool::ScriptParse parsed = tool::load_script(path);
  if (!parsed) return parsed.error();
  return make(*parsed, path, tools, held);
}

std::vector<tool::ScriptPlayer::ToolInfo> ActionScriptHand::tool_infos(const SessionCase& scene) {
  std::vector<tool::ScriptPlayer::ToolInfo> out;
  const std::vector<tool::CaseAspiration>& vacuum = scene.spec.aspiration;
  for (const tool::ToolSpec& spec : scene.spec.tools) {
    out.push_back(tool::tool_info(spec));
    out.back().aspirator = std::any_of(vacuum.begin(), vacuum.end(), [&](const tool::CaseAspiration& a) { return a.tool == spec.name; });
  }
  return out;
}

base::Result<std::unique_ptr<ActionScriptHand>> ActionScriptHand::load(const std::string& path,
                                                                       const SessionCase& scene) {
  return load(path, tool_infos(scene), 0);
}

base::Result<std::unique_ptr<ActionScriptHand>> ActionScriptHand::make(
    const tool::Script& script, const std::string& name, const std::vector<tool::ScriptPlayer::ToolInfo>& tools,
    std::size_t held) {
  base::Result<tool::ScriptPlayer> player = tool::ScriptPlayer::make(script, tools, held, name);
  if (!player) return base::Error{player.error().message};
  return std::unique_ptr<ActionScriptHand>(new ActionScriptHand(std::move(*player), name));
}

void ActionScriptHand::controls(std::int64_t tick, ControlSink& sink) {
  if (finished_) return;
  // The player applies the actions due at this millisecond and moves its motions by one.
  const tool::ScriptPlayer::Step step = player_.advance(tick);
  if (step.selected) sink.push(Control::select_tool(*step.selected));
  // The imaging verbs become the fluoroscopy unit's controls, recorded like a trainee's.
  for (const tool::Action& a : step.due) {
    if (const std::optional<Control> c = fluoro_control::from_action(a)) sink.push(*c);
  }
  if (step.detach) sink.push(Control::detach_coil(*step.detach));
  if (step.load_coil) sink.push(Control::load_coil(*step.load_coil));
  for (std::size_t i = 0; i < step.device_count; ++i) {  // inflate / deflate: the balloon's controls
    const tool::ScriptPlayer::DeviceAction& a = step.devices[i];
    const BalloonOp op = a.kind == tool::ActionKind::kInflatePressure ? BalloonOp::kInflatePressure
                         : a.kind == tool::ActionKind::kInflateVolume ? BalloonOp::kInflateVolume
                                                                      : BalloonOp::kDeflate;
    sink.push(Control::balloon(a.tool, op, a.value));
  }
  for (std::size_t i = 0; i < step.clot_device_count; ++i) {  // aspiration / balloon_guide: the thrombectomy unit's
    const tool::ScriptPlayer::DeviceAction& a = step.clot_devices[i];
    const bool on = a.value != 0.0;
    sink.push(a.kind == tool::ActionKind::kAspiration ? Control::aspiration(a.tool, on) : Control::balloon_guide(a.tool, on));
  }
  if (step.ended) {
    ended_ = true;
    finished_ = true;
  }
}

void ActionScriptHand::read(std::int64_t tick, TickInput& in) {
  if (ended_) return;  // `end`: the tools stay where they are
  for (std::size_t t = 0; t < in.tool_count; ++t) {
    in.tools[t] = {std::llround(player_.insertion_mm(t) * 1e3), std::llround(player_.rotation_rad(t) * 1e6)};
  }
  // As `cathbox sim run`: once everything is done, stop after the tools have settled.
  if (player_.settled(tick, kSettle_ms)) finished_ = true;
}

std::string ActionScriptHand::finish_reason() const {
  return ended_ ? "action script: end" : "action script: done (all motions ended " + std::to_string(kSettle_ms) + " ms ago)";
}

}  // namespace cathbox::session

#include "scenario/script_player.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "tool/rod.hpp"
#include "base/text_lines.hpp"

namespace cathbox::tool {

using base::text::located;
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Moves `value` towards the motion's target by one millisecond.
template <class Motion>
double advance_motion(Motion& m, double value) {
  if (!m.active) return value;
  const double d = m.target - value;
  if (std::abs(d) <= m.speed_per_ms) {
    m.active = false;
    return m.target;
  }
  return value + (d > 0.0 ? m.speed_per_ms : -m.speed_per_ms);
}

// Walks a script's actions as the player will, checking each against the tool selected then:
// a coil is detached before the next is loaded, a balloon verb meets a balloon, an aspiration a
// vacuum source, a selected tool exists.
class ScriptCheck {
  using ToolInfo = ScriptPlayer::ToolInfo;

 public:
  ScriptCheck(std::span<const ToolInfo> tools, std::size_t selected)
      : tools_(tools), current_(selected), loads_(tools.size(), 0), released_(tools.size(), false) {}

  // Empty, or what is wrong with `a` at this point of the script.
  std::string action(const Action& a) {
    if (a.kind == ActionKind::kDetach && current_ < tools_.size()) released_[current_] = true;
    if (a.kind == ActionKind::kLoadCoil) {
      std::string problem = load_coil();
      if (!problem.empty()) return problem;
    }
    if (is_balloon(a.kind) && !selected_has(&ToolInfo::balloon)) {
      const std::string verb = a.kind == ActionKind::kDeflate ? "deflate" : "inflate";
      const std::string name = current_ < tools_.size() ? tools_[current_].name : "?";
      return verb + ": tool '" + name + "' has no balloon";
    }
    if (a.kind == ActionKind::kBalloonGuide && !selected_has(&ToolInfo::balloon)) {
      return "balloon_guide: tool '" + who() + "' has no balloon";
    }
    if (a.kind == ActionKind::kAspiration && !selected_has(&ToolInfo::aspirator)) {
      return "aspiration: tool '" + who() + "' has no vacuum source (the case's `aspiration` names the catheter that has)";
    }
    if (a.kind == ActionKind::kDetach && !selected_has(&ToolInfo::coil)) return "detach: '" + who() + "' carries no coil";
    if (a.kind == ActionKind::kSelect) return select(a.tool);
    return {};
  }

 private:
  [[nodiscard]] std::string who() const { return current_ < tools_.size() ? tools_[current_].name : std::string("no tool"); }
  // The tool selected now carries `device` (coil, balloon, aspirator).
  [[nodiscard]] bool selected_has(bool ToolInfo::*device) const { return current_ < tools_.size() && tools_[current_].*device; }

  std::string load_coil() {
    if (!selected_has(&ToolInfo::coil)) return "load_coil: '" + who() + "' carries no coil";
    const std::size_t listed = tools_[current_].next_coil_max_insertion_mm.size();
    if (loads_[current_] >= listed) {
      return "load_coil: '" + who() + "' has no further coil (the case lists " + std::to_string(listed) + " after the first)";
    }
    if (!released_[current_]) return "load_coil: the coil of '" + who() + "' is not detached yet";
    ++loads_[current_];
    released_[current_] = false;
    return {};
  }

  std::string select(const std::string& tool) {
    const auto found = std::find_if(tools_.begin(), tools_.end(), [&](const ToolInfo& t) { return t.name == tool; });
    current_ = static_cast<std::size_t>(found - tools_.begin());
    if (found != tools_.end()) return {};
    std::string names;
    for (std::size_t i = 0; i < tools_.size(); ++i) names += (i ? " " : "") + tools_[i].name;
    return "select: the case has no tool '" + tool + "' (tools: " + names + ")";
  }

  std::span<const ToolInfo> tools_;
  std::size_t current_;
  std::vector<std::size_t> loads_;
  std::vector<bool> released_;
};

}  // namespace

base::Result<ScriptPlayer> ScriptPlayer::make(const Script& script, std::span<const ToolInfo> tools,
                                              std::size_t selected, const std::string& script_name) {
  ScriptCheck check(tools, selected);
  for (const Action& a : script.actions) {
    const std::string problem = check.action(a);
    if (!problem.empty()) return base::Error{located(script_name, a.line, problem)};
  }
  return ScriptPlayer(script, tools, selected);
}

ScriptPlayer::ScriptPlayer(const Script& script, std::span<const ToolInfo> tools, std::size_t selected)
    : actions_(script.actions),
      insert_(tools.size()),
      rotate_(tools.size()),
      insertion_(tools.size(), 0.0),
      rotation_(tools.size(), 0.0),
      selected_(selected) {
  for (const ToolInfo& t : tools) {
    names_.push_back(t.name);
    max_insertion_mm_.push_back(t.max_insertion_mm);
    next_max_insertion_mm_.push_back(t.next_coil_max_insertion_mm);
  }
  loaded_.assign(tools.size(), 0);
  last_action_ms_ = actions_.empty() ? 0 : actions_.back().time_ms;
  has_end_ = std::any_of(actions_.begin(), actions_.end(), [](const Action& a) { return a.kind == ActionKind::kEnd; });
}

ScriptPlayer::Step ScriptPlayer::advance(std::int64_t now_ms) {
  Step step;
  const std::size_t first = next_;
  for (; next_ < actions_.size() && actions_[next_].time_ms <= now_ms; ++next_) {
    const Action& a = actions_[next_];
    const std::size_t t = selected_;
    if (is_balloon(a.kind) && step.device_count == kMaxDeviceActions) break;
    if (is_thrombectomy(a.kind) && step.clot_device_count == kMaxDeviceActions) break;
    switch (a.kind) {
      case ActionKind::kSelect:
        selected_ = static_cast<std::size_t>(std::find(names_.begin(), names_.end(), a.tool) - names_.begin());
        step.selected = selected_;
        break;
      case ActionKind::kEnd: step.ended = true; break;
      case ActionKind::kDetach:
        step.detach = t;
        step.detach_line = a.line;
        break;
      case ActionKind::kLoadCoil:
        // The new pusher enters at the hub: insertion and rotation start again from 0.
        step.load_coil = t;
        step.load_coil_line = a.line;
        if (loaded_[t] < next_max_insertion_mm_[t].size()) max_insertion_mm_[t] = next_max_insertion_mm_[t][loaded_[t]++];
        insert_[t].active = false;
        rotate_[t].active = false;
        insertion_[t] = 0.0;
        rotation_[t] = 0.0;
        break;
      case ActionKind::kInsertTo:
      case ActionKind::kInsertBy:
        insert_[t].active = true;
        insert_[t].target = a.kind == ActionKind::kInsertTo ? a.value : insertion_[t] + a.value;
        insert_[t].target = std::clamp(insert_[t].target, 0.0, max_insertion_mm_[t]);
        insert_[t].speed_per_ms = a.speed / 1000.0;
        break;
      case ActionKind::kRotateTo:
      case ActionKind::kRotateBy:
        rotate_[t].active = true;
        rotate_[t].target = a.kind == ActionKind::kRotateTo ? a.value * kDegToRad : rotation_[t] + a.value * kDegToRad;
        rotate_[t].speed_per_ms = a.speed * kDegToRad / 1000.0;
        break;
      case ActionKind::kFluoro:
      case ActionKind::kInject:
      case ActionKind::kCArm:
      case ActionKind::kRoadmap:
        break;  // imaging: acted on by the fluoroscopy unit (step.due), not by the tools
      case ActionKind::kInflatePressure:
      case ActionKind::kInflateVolume:
      case ActionKind::kDeflate:
        step.devices[step.device_count++] = DeviceAction{a.kind, a.value, t, a.line};
        break;
      case ActionKind::kAspiration:
      case ActionKind::kBalloonGuide:
        step.clot_devices[step.clot_device_count++] = DeviceAction{a.kind, a.value, t, a.line};
        break;
    }
  }
  step.due = std::span<const Action>(actions_).subspan(first, next_ - first);
  if (step.ended) return step;
  moving_ = false;
  for (std::size_t t = 0; t < insertion_.size(); ++t) {
    insertion_[t] = advance_motion(insert_[t], insertion_[t]);
    rotation_[t] = advance_motion(rotate_[t], rotation_[t]);
    moving_ = moving_ || insert_[t].active || rotate_[t].active;
  }
  return step;
}

bool ScriptPlayer::settled(std::int64_t now_ms, std::int64_t settle_ms) {
  if (has_end_ || next_ < actions_.size() || now_ms < last_action_ms_) return false;
  if (moving_) {
    idle_since_ms_ = -1;
    return false;
  }
  if (idle_since_ms_ < 0) {
    idle_since_ms_ = now_ms;
    return false;
  }
  return now_ms - idle_since_ms_ >= settle_ms;
}

ScriptPlayer::ToolInfo tool_info(const ToolSpec& spec) {
  ScriptPlayer::ToolInfo info{spec.name, Rod(spec).max_insertion_mm(), spec.kind == ToolKind::kCoil && spec.detach_mm > 0.0,
                              spec.balloon.present(), {}};
  for (std::size_t k = 0; k < spec.next_coils.size(); ++k) info.next_coil_max_insertion_mm.push_back(Rod(with_next_coil(spec, k)).max_insertion_mm());
  return info;
}

}  // namespace cathbox::tool

#pragma once
// The trainee's hand as the session's haptic tick sees it: one interface, one implementation
// per file (box_hand, keyboard_hand, scripted_hand, action_script_hand, replay_hand,
// program_hand).
//
// Each tick the session (1) applies the controls of the tick — those posted by the UI and those
// the hand issues itself (controls()), (2) asks the hand where the tools are (read()), (3)
// steps the simulation, (4) tells the hand what it feels (feel()). Tool positions are integers
// (micrometres, microradians): the simulator consumes exactly what the record stores.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <glm/vec3.hpp>

#include "session/device_record.hpp"
#include "tool/force_law.hpp"
#include "tool/tool_spec.hpp"

namespace cathbox::session {

class ControlSink;
struct Control;

// The tools a case has at most (tool::ToolLimits, sim/tool/README.md): 6, balloon-assisted
// coiling's guide, balloon catheter and its wire, microcatheter, microwire and coil.
inline constexpr std::size_t kMaxTools = tool::ToolLimits::kMaxTools;
// Released coils a scene snapshot carries (drawn in the 3D view and the fluoroscopy); coils
// released beyond these are simulated but not drawn.
inline constexpr std::size_t kMaxReleasedCoils = 16;

// One tool's commanded position at the entry.
struct ToolCommand {
  std::int64_t insertion_um = 0;
  std::int64_t rotation_urad = 0;
  friend bool operator==(const ToolCommand&, const ToolCommand&) = default;
};

// What a box reports besides positions (recorded when it changes).
struct BoxStatus {
  bool present = false;      // the hand is a box
  bool link_up = false;
  std::uint16_t faults = 0;  // CBX_FAULT_* latched in the box
  friend bool operator==(const BoxStatus&, const BoxStatus&) = default;
};

// The hand's answer for one tick. The session fills it with the previous tick's commands, the
// held tool (after this tick's controls) and the limits; the hand changes what it moves.
struct TickInput {
  std::size_t tool_count = 0;
  std::size_t held = 0;
  std::array<ToolCommand, kMaxTools> tools{};
  std::array<std::int64_t, kMaxTools> max_insertion_um{};  // the session clamps to [0, max]
  BoxStatus box{};
};

// What the trainee's hand feels after the step (and what the autopilot looks at).
struct HandFeedback {
  std::int64_t tick = 0;
  std::size_t held = 0;
  tool::ForceLaw law;           // the held tool's local force law, in the session's frame
  // Every tool's force law (laws[held] == law), filled only for hands that render every tool
  // (Hand::feels_every_tool(): a box per tool); else tool_count is 0.
  std::size_t tool_count = 0;
  std::array<tool::ForceLaw, kMaxTools> laws{};
  glm::vec3 tip_mm{0.0F};       // the held tool's tip
  glm::vec3 tip_direction{1.0F, 0.0F, 0.0F};
  glm::vec3 tip_bend{0.0F, 1.0F, 0.0F};
  double hand_force_mN = 0.0;   // axial force resisting the push
  std::optional<std::uint64_t> state_hash;  // on the ticks the record holds a hash
};

enum class HandKind : std::uint8_t {
  kBox = 1,           // a box through BoxClient (real or emulated)
  kKeyboard = 2,      // keyboard and mouse
  kScripted = 3,      // the autopilot
  kActionScript = 4,  // a *.actions script
  kReplay = 5,        // a record
  kProgram = 6,       // a program's speeds (the Python module's environments)
};
[[nodiscard]] const char* hand_kind_name(HandKind kind);

class Hand {
 public:
  virtual ~Hand() = default;
  [[nodiscard]] virtual HandKind kind() const = 0;
  // One line: what drives the tools ("emulated box: emulator 1209:cb01 /tmp/x.sock", ...).
  [[nodiscard]] virtual std::string describe() const = 0;
  // The box behind the hand, for the record (none for hands without a box).
  [[nodiscard]] virtual std::optional<DeviceRecord> device() const;

  // Haptic thread. Controls this hand issues at `tick` (an action script's `select`, a
  // record's controls), applied before read().
  virtual void controls(std::int64_t tick, ControlSink& sink);
  // Haptic thread. The held tool changed (a select control): single-tool hands carry on from
  // where that tool is.
  virtual void hold(std::size_t tool, const ToolCommand& at);
  // Haptic thread. `tool` starts again at `at` (a coil loaded at the hub, load_coil): a hand
  // driving it carries on from there, wherever the trainee's hand physically is. Scripts and
  // replays move it themselves.
  virtual void restart(std::size_t tool, const ToolCommand& at);
  // Haptic thread: where the tools are at `tick`.
  virtual void read(std::int64_t tick, TickInput& input) = 0;
  // Haptic thread, after the step.
  virtual void feel(const HandFeedback& feedback);
  // True when feel() needs every tool's law (HandFeedback::laws), not only the held one's;
  // asked once, when the session starts.
  [[nodiscard]] virtual bool feels_every_tool() const { return false; }
  // Outputs off (end of run, shutdown).
  virtual void release();

  // The hand has nothing more to do (script ended, autopilot stuck, record over); the reason is
  // asked once, when the session ends the run.
  [[nodiscard]] virtual bool finished() const;
  [[nodiscard]] virtual std::string finish_reason() const;
};

// Where a hand's controls go (the session applies them as they come).
class ControlSink {
 public:
  virtual ~ControlSink() = default;
  virtual void push(const Control& control) = 0;
};

}  // namespace cathbox::session

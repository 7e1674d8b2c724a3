#pragma once
// Discrete controls: things a trainee does at one instant rather than continuously (take the
// other tool in the hand; later: press the fluoroscopy pedal, inject contrast, turn the C-arm,
// detach a coil, inflate a balloon). Any thread posts them (the UI), the haptic thread applies
// them at the start of its next tick, and the record stores each applied control in that
// tick, so a replay applies the same controls at the same ticks.
//
// A control is a kind (a number from the table below) and up to 32 bytes of payload, encoded
// with explicit byte order by whoever defines the kind. Adding a kind (host/session/README.md,
// "Adding a control kind"): pick a number in your module's range, add it to ControlKind and to
// known_control_kind(), write a ControlHandler, and register it with Session::add_control_handler
// in every front end that runs your module. A record holding a kind an older reader does not
// know is refused with "unknown kind N at byte X", never misread.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>

#include "session/spsc_ring.hpp"

namespace cathbox::tool {
class Simulator;
}

namespace cathbox::session {

class Hand;
class EventLog;
struct TickInput;

// Control kinds. Ranges: 16..31 the session itself; 32..63 fluoroscopy (pedal, injection,
// C-arm, roadmap); 64..95 devices (coil detach, balloon inflate, ...); 96..127 free. The numbers
// share one space with the record's per-tick entry kinds (record_format.hpp), 0..15.
enum class ControlKind : std::uint16_t {
  kSelectTool = 16,  // payload: u8 tool index, or 0xFF for "the next tool"
  // Fluoroscopy (session/fluoro_controls.hpp has the makers and payloads).
  kFluoroPedal = 32,   // u8 1 pressed, 0 released
  kInject = 33,        // f64 volume mL, f64 rate mL/s
  kCArmAngles = 34,    // f64 LAO degrees (RAO negative), f64 cranial degrees (caudal negative)
  kCArmGeometry = 35,  // f64 SID mm, f64 table height mm, f64 field of view mm, f64 collimation
  kPulseRate = 36,     // u16 pulses per 10 s (75, 150, 300)
  kRoadmap = 37,       // u8 1 capture, 0 clear
  kDetachCoil = 64,  // payload: u8 index of the coil tool whose coil is released
  kBalloon = 65,     // payload: u8 tool index, u8 BalloonOp, f64 value (atm or ml; 0 for deflate)
  kLoadCoil = 66,    // payload: u8 index of the coil tool that takes its next coil (old pusher out)
  kAspiration = 67,   // payload: u8 index of the aspiration catheter, u8 1 on / 0 off (thrombectomy_unit.hpp)
  kBalloonGuide = 68, // payload: u8 index of the balloon guide catheter, u8 1 inflate / 0 deflate
};

// What a kBalloon control asks of the inflation device.
enum class BalloonOp : std::uint8_t { kInflatePressure = 0, kInflateVolume = 1, kDeflate = 2 };

// True for the kinds this build knows how to replay.
[[nodiscard]] bool known_control_kind(std::uint16_t kind);
// A known kind's name ("select_tool", "fluoro_pedal", "inject", "carm_angles", "carm_geometry",
// "pulse_rate", "roadmap", "detach_coil", "balloon", "load_coil", "aspiration", "balloon_guide"),
// null for others.
[[nodiscard]] const char* control_kind_name(std::uint16_t kind);
// The known kinds as text, for errors: "16, 32-37, 64-68".
[[nodiscard]] const char* known_control_kinds();

struct Control {
  static constexpr std::size_t kMaxPayload = 32;
  std::uint16_t kind = 0;
  std::uint8_t size = 0;
  std::array<std::uint8_t, kMaxPayload> payload{};

  [[nodiscard]] std::span<const std::uint8_t> bytes() const { return {payload.data(), size}; }
  // A control of `kind` with `bytes` (at most kMaxPayload) as payload.
  [[nodiscard]] static Control make(std::uint16_t kind, std::span<const std::uint8_t> bytes);
  [[nodiscard]] static Control select_tool(std::size_t tool);
  [[nodiscard]] static Control select_next_tool();
  [[nodiscard]] static Control detach_coil(std::size_t tool);
  [[nodiscard]] static Control load_coil(std::size_t tool);
  [[nodiscard]] static Control balloon(std::size_t tool, BalloonOp op, double value);
  [[nodiscard]] static Control aspiration(std::size_t tool, bool on);
  [[nodiscard]] static Control balloon_guide(std::size_t tool, bool inflate);
};

// What a handler may touch while it applies a control (haptic thread, between two ticks).
struct ControlContext {
  std::int64_t tick = 0;
  std::int64_t time_us = 0;
  tool::Simulator& sim;
  Hand& hand;
  EventLog& events;
  const TickInput& input;  // the tools' commands as of the last tick
};

class ControlHandler {
 public:
  virtual ~ControlHandler() = default;
  // Applies `control` at a tick boundary. It may rewrite the control into the form to record
  // (e.g. "next tool" becomes the tool's index); false drops it: not applied, not recorded.
  // Runs on the haptic thread: no blocking, no allocation.
  [[nodiscard]] virtual bool apply(Control& control, ControlContext& context) = 0;
};

// Many producers (any thread; they take a mutex among themselves), one consumer (the haptic
// thread, which never waits). Bounded: post() on a full queue returns false.
class ControlQueue {
 public:
  static constexpr std::size_t kCapacity = 64;

  bool post(const Control& control);
  // Consumer only.
  bool pop(Control& out);
  // After close() every post() fails (a replay takes its controls from the record only).
  void close() { closed_.store(true, std::memory_order_release); }

 private:
  SpscRing<Control, kCapacity> ring_;
  std::mutex producers_;
  std::atomic<bool> closed_{false};
};

}  // namespace cathbox::session

#include "session/control.hpp"

#include <algorithm>
#include <cassert>
#include <cstring>

namespace cathbox::session {

const char* control_kind_name(std::uint16_t kind) {
  switch (static_cast<ControlKind>(kind)) {
    case ControlKind::kSelectTool: return "select_tool";
    case ControlKind::kFluoroPedal: return "fluoro_pedal";
    case ControlKind::kInject: return "inject";
    case ControlKind::kCArmAngles: return "carm_angles";
    case ControlKind::kCArmGeometry: return "carm_geometry";
    case ControlKind::kPulseRate: return "pulse_rate";
    case ControlKind::kRoadmap: return "roadmap";
    case ControlKind::kDetachCoil: return "detach_coil";
    case ControlKind::kBalloon: return "balloon";
    case ControlKind::kLoadCoil: return "load_coil";
    case ControlKind::kAspiration: return "aspiration";
    case ControlKind::kBalloonGuide: return "balloon_guide";
  }
  return nullptr;
}

bool known_control_kind(std::uint16_t kind) { return control_kind_name(kind) != nullptr; }

const char* known_control_kinds() { return "16, 32-37, 64-68"; }

Control Control::make(std::uint16_t kind, std::span<const std::uint8_t> bytes) {
  assert(bytes.size() <= kMaxPayload);
  Control c;
  c.kind = kind;
  c.size = static_cast<std::uint8_t>(std::min(bytes.size(), kMaxPayload));
  std::copy_n(bytes.begin(), c.size, c.payload.begin());
  return c;
}

Control Control::select_tool(std::size_t tool) {
  const std::uint8_t b = static_cast<std::uint8_t>(std::min<std::size_t>(tool, 0xFE));
  return make(static_cast<std::uint16_t>(ControlKind::kSelectTool), std::span(&b, 1));
}

Control Control::select_next_tool() {
  const std::uint8_t b = 0xFF;
  return make(static_cast<std::uint16_t>(ControlKind::kSelectTool), std::span(&b, 1));
}

bool ControlQueue::post(const Control& control) {
  if (closed_.load(std::memory_order_acquire)) return false;
  const std::lock_guard lock(producers_);
  return ring_.push(control);
}

Control Control::balloon(std::size_t tool, BalloonOp op, double value) {
  std::array<std::uint8_t, 10> b{static_cast<std::uint8_t>(tool), static_cast<std::uint8_t>(op)};
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 8; ++i) b[2 + i] = static_cast<std::uint8_t>(bits >> (8 * i));  // little endian
  return make(static_cast<std::uint16_t>(ControlKind::kBalloon), b);
}

bool ControlQueue::pop(Control& out) { return ring_.pop(out); }

Control Control::detach_coil(std::size_t tool) {
  const auto b = static_cast<std::uint8_t>(tool);
  return make(static_cast<std::uint16_t>(ControlKind::kDetachCoil), std::span(&b, 1));
}

Control Control::load_coil(std::size_t tool) {
  const auto b = static_cast<std::uint8_t>(tool);
  return make(static_cast<std::uint16_t>(ControlKind::kLoadCoil), std::span(&b, 1));
}

Control Control::aspiration(std::size_t tool, bool on) {
  const std::array<std::uint8_t, 2> b{static_cast<std::uint8_t>(tool), static_cast<std::uint8_t>(on ? 1 : 0)};
  return make(static_cast<std::uint16_t>(ControlKind::kAspiration), b);
}

Control Control::balloon_guide(std::size_t tool, bool inflate) {
  const std::array<std::uint8_t, 2> b{static_cast<std::uint8_t>(tool), static_cast<std::uint8_t>(inflate ? 1 : 0)};
  return make(static_cast<std::uint16_t>(ControlKind::kBalloonGuide), b);
}

}  // namespace cathbox::session

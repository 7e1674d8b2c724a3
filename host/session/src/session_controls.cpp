#include "session_controls.hpp"

#include <cstring>

namespace cathbox::session {

bool Session::SelectTool::apply(Control& c, ControlContext& ctx) {
  if (c.size != 1) return false;
  const std::size_t count = ctx.sim.tool_count();
  std::size_t next = c.payload[0];
  if (next == 0xFF) next = (ctx.sim.active_tool() + 1) % count;
  if (next >= count || next == ctx.sim.active_tool()) return false;
  ctx.sim.select(next);
  ctx.hand.hold(next, ctx.input.tools[next]);
  c.payload[0] = static_cast<std::uint8_t>(next);  // recorded as the tool it became
  s_.tool_changed_ = true;
  s_.held_.store(next, std::memory_order_relaxed);
  s_.log("now holding the %s", s_.tool_names_[next].c_str());
  return true;
}

bool Session::DetachCoil::apply(Control& c, ControlContext& ctx) {
  if (c.size != 1) return false;
  if (!s_.device_done(ctx.sim.detach(c.payload[0]), "detach")) return false;
  s_.log("detaching the coil of the %s: its zone parts in 0.1 s", s_.tool_names_[c.payload[0]].c_str());
  return true;
}

bool Session::LoadCoil::apply(Control& c, ControlContext& ctx) {
  if (c.size != 1) return false;
  if (!s_.device_done(ctx.sim.load_next_coil(c.payload[0]), "load_coil")) {
    if (ctx.hand.kind() == HandKind::kActionScript) {
      // The script has already moved on to the next coil: its motions would drive the coil
      // still attached from the hub (a pull of its whole length in one tick).
      s_.log("the script's next coil is not loaded: run ended");
      s_.end_run();
    }
    return false;
  }
  const std::size_t t = c.payload[0];
  if (t < kMaxTools) {
    s_.update_max_insertion(t);
    // The new pusher starts at the hub: every hand driving this tool carries on from 0.
    s_.input_.tools[t] = ToolCommand{};
    ctx.hand.restart(t, s_.input_.tools[t]);
  }
  s_.coil_loaded_ = t == ctx.sim.active_tool();  // the held tool's samples start again
  s_.log("next coil loaded on the %s", s_.tool_names_[t].c_str());
  return true;
}

bool Session::BalloonControl::apply(Control& c, ControlContext& ctx) {
  if (c.size != 10 || c.payload[1] > 2) return false;
  const std::size_t tool = c.payload[0];
  std::uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= static_cast<std::uint64_t>(c.payload[2 + i]) << (8 * i);
  double value = 0.0;
  std::memcpy(&value, &bits, sizeof value);
  const auto op = static_cast<BalloonOp>(c.payload[1]);
  const tool::DeviceError e = op == BalloonOp::kInflatePressure ? ctx.sim.inflate_pressure(tool, value)
                              : op == BalloonOp::kInflateVolume  ? ctx.sim.inflate_volume(tool, value)
                                                                 : ctx.sim.deflate(tool);
  if (e != tool::DeviceError::kNone) {
    s_.log("balloon: refused (%s)", tool::device_error_text(e));
    return false;
  }
  if (op == BalloonOp::kDeflate) {
    s_.log("balloon of the %s: deflate", s_.tool_names_[tool].c_str());
  } else {
    s_.log("balloon of the %s: inflate to %.2f %s", s_.tool_names_[tool].c_str(), value,
           op == BalloonOp::kInflatePressure ? "atm" : "ml");
  }
  return true;
}

}  // namespace cathbox::session

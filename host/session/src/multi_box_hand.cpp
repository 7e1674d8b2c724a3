#include "session/multi_box_hand.hpp"

#include <cstdio>

namespace cathbox::session {

base::Result<BoxBinding> parse_box_binding(const std::string& text, std::span<const tool::ToolSpec> tools) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    return base::Error{"--box '" + text + "': needs TOOL=WHERE (a serial, emu or emu:PATH)"};
  }
  BoxBinding b;
  b.tool_name = text.substr(0, eq);
  const std::string where = text.substr(eq + 1);
  std::string names;
  bool found = false;
  for (std::size_t t = 0; t < tools.size(); ++t) {
    names += (t == 0 ? "" : ", ") + tools[t].name;
    if (!found && tools[t].name == b.tool_name) {
      b.tool = t;
      found = true;
    }
  }
  if (!found) return base::Error{"--box '" + text + "': the case has no tool '" + b.tool_name + "' (its tools: " + names + ")"};
  if (where == "emu") {
    b.source = BoxSource::kEmulator;
  } else if (where.starts_with("emu:")) {
    b.source = BoxSource::kEmulator;
    b.socket = where.substr(4);
    if (b.socket.empty()) return base::Error{"--box '" + text + "': emu: needs a socket path"};
  } else {
    b.source = BoxSource::kSerial;
    b.serial = where;
  }
  return b;
}

base::Result<std::unique_ptr<MultiBoxHand>> MultiBoxHand::connect(std::span<const BoxBinding> bindings,
                                                                  const BoxHandOptions& options, std::size_t tool_count) {
  std::vector<Bound> boxes;
  int started = 0;
  for (const BoxBinding& b : bindings) {
    BoxHandOptions o = options;
    o.source = b.source;
    o.emu_socket = b.socket;
    o.serial = b.serial;
    o.tool = b.tool;
    if (b.source == BoxSource::kEmulator && b.socket.empty()) {
      char serial[16];
      std::snprintf(serial, sizeof serial, "EMU-%04d", ++started);
      o.emu_args.insert(o.emu_args.end(), {"--serial", serial});
    }
    base::Result<std::unique_ptr<BoxHand>> box = BoxHand::connect(o);
    if (!box) return base::Error{"box for '" + b.tool_name + "': " + box.error().message};
    boxes.push_back({std::move(*box), b.tool_name});
  }
  return make(std::move(boxes), tool_count);
}

base::Result<std::unique_ptr<MultiBoxHand>> MultiBoxHand::make(std::vector<Bound> boxes, std::size_t tool_count) {
  if (boxes.size() < 2) {
    return base::Error{"a rig with a box per tool needs two boxes or more (one box switches between tools)"};
  }
  std::vector<bool> taken(tool_count, false);
  for (const Bound& b : boxes) {
    const std::optional<std::size_t> tool = b.box ? b.box->bound_tool() : std::nullopt;
    if (!tool) return base::Error{"box for '" + b.tool_name + "' is not bound to a tool"};
    if (*tool >= tool_count) {
      return base::Error{"box for '" + b.tool_name + "': the case has " + std::to_string(tool_count) + " tools"};
    }
    if (taken[*tool]) return base::Error{"two boxes drive '" + b.tool_name + "'"};
    taken[*tool] = true;
  }
  return std::unique_ptr<MultiBoxHand>(new MultiBoxHand(std::move(boxes)));
}

std::string MultiBoxHand::describe() const {
  std::string out = std::to_string(boxes_.size()) + " boxes:";
  for (std::size_t i = 0; i < boxes_.size(); ++i) {
    const std::optional<DeviceRecord> d = boxes_[i].box->device();
    out += (i == 0 ? " " : "; ") + boxes_[i].tool_name + " <- " + (d ? "serial " + d->serial + ", " : "") +
           boxes_[i].box->describe();
  }
  return out;
}

std::optional<DeviceRecord> MultiBoxHand::device() const { return boxes_.front().box->device(); }

void MultiBoxHand::hold(std::size_t tool, const ToolCommand& at) {
  for (Bound& b : boxes_) b.box->hold(tool, at);
}

void MultiBoxHand::restart(std::size_t tool, const ToolCommand& at) {
  for (Bound& b : boxes_) b.box->restart(tool, at);
}

void MultiBoxHand::read(std::int64_t tick, TickInput& input) {
  BoxStatus all{true, true, 0};
  for (Bound& b : boxes_) {
    b.box->read(tick, input);
    all.link_up = all.link_up && input.box.link_up;
    all.faults = static_cast<std::uint16_t>(all.faults | input.box.faults);
  }
  input.box = all;
}

void MultiBoxHand::feel(const HandFeedback& feedback) {
  for (Bound& b : boxes_) b.box->feel(feedback);
}

void MultiBoxHand::release() {
  for (Bound& b : boxes_) b.box->release();
}

}  // namespace cathbox::session

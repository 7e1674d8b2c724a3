#pragma once
// A rig with a box per tool: the trainee holds the microcatheter in one box and the microwire
// in the other (issue 16, "two boxes on one rig"). Each box is a BoxHand bound to its tool
// (BoxHandOptions::tool): it drives that tool's insertion and rotation and renders that tool's
// force law, whichever tool the UI calls "held"; a tool without a box stays where it is (or
// moves with the keyboard when it is the held one and no box drives it). The tick's box status
// is the boxes' together: present, link up only when every link is up, faults OR-ed.
// With one box, use BoxHand unbound instead: one box switches between tools ("tool in hand").
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/result.hpp"
#include "session/box_hand.hpp"
#include "session/hand.hpp"
#include "tool/tool_spec.hpp"

namespace cathbox::session {

// One box of a rig and the tool it holds, as `--box TOOL=WHERE` gives it: WHERE is a real box's
// serial, `emu` (an emulator started for it, serial EMU-000N for the N-th) or `emu:PATH`.
struct BoxBinding {
  std::size_t tool = 0;
  std::string tool_name;
  BoxSource source = BoxSource::kEmulator;
  std::string socket;  // kEmulator: connect here; empty: start one
  std::string serial;  // kSerial
};
// Parses TOOL=WHERE against the case's tools, or one line saying what is wrong.
[[nodiscard]] base::Result<BoxBinding> parse_box_binding(const std::string& text, std::span<const tool::ToolSpec> tools);

class MultiBoxHand final : public Hand {
 public:
  struct Bound {
    std::unique_ptr<BoxHand> box;  // bound to a tool (BoxHandOptions::tool)
    std::string tool_name;         // for describe()
  };
  // Two or more boxes, each bound to a different tool below tool_count; else one line.
  [[nodiscard]] static base::Result<std::unique_ptr<MultiBoxHand>> make(std::vector<Bound> boxes, std::size_t tool_count);
  // Connects (or starts) every box of `bindings` with `options`' other fields (emu_program,
  // dt_s, keyboard); one line naming the box's tool when one fails.
  [[nodiscard]] static base::Result<std::unique_ptr<MultiBoxHand>> connect(std::span<const BoxBinding> bindings,
                                                                           const BoxHandOptions& options,
                                                                           std::size_t tool_count);

  [[nodiscard]] HandKind kind() const override { return HandKind::kBox; }
  [[nodiscard]] std::string describe() const override;
  // The first box (the record's header holds one device; describe() names them all).
  [[nodiscard]] std::optional<DeviceRecord> device() const override;
  void hold(std::size_t tool, const ToolCommand& at) override;
  void restart(std::size_t tool, const ToolCommand& at) override;
  void read(std::int64_t tick, TickInput& input) override;
  void feel(const HandFeedback& feedback) override;
  [[nodiscard]] bool feels_every_tool() const override { return true; }
  void release() override;

  [[nodiscard]] std::size_t size() const { return boxes_.size(); }
  [[nodiscard]] const BoxHand& box(std::size_t i) const { return *boxes_[i].box; }

 private:
  explicit MultiBoxHand(std::vector<Bound> boxes) : boxes_(std::move(boxes)) {}
  std::vector<Bound> boxes_;
};

}  // namespace cathbox::session

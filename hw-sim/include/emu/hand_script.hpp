#pragma once
// What the trainee's hand does to one axis over time: a list of segments, each holding the
// tool at a velocity (the hand follows a moving target through its own stiffness and damping,
// so the brake or motor still acts on the motion) or pushing with a force. After the last
// segment the hand lets go (zero force).
#include <cstdint>
#include <string>
#include <vector>

#include "emu/result.hpp"

namespace cathbox::emu {

enum class HandMode { kVelocity, kForce, kFree };

struct HandSegment {
  uint64_t duration_us = 0;
  HandMode mode = HandMode::kFree;
  double value = 0.0;  // the model's SI units: m/s (rad/s) for velocity; N (N*m) for force
};

class HandScript {
 public:
  HandScript() = default;
  explicit HandScript(std::vector<HandSegment> segments) : segments_(std::move(segments)) {}
  // "v:20mm/s:2s,f:-1500mN:500ms,free:1s": mode:value:duration, every value with its unit in
  // the project's units: mm/s and mN on the insertion axis, rad/s and mNmm (mN*mm) on the
  // rotation axis; durations in s, ms or us. One script drives one axis (its units agree); with
  // `axis` (0 insertion, 1 rotation) they must be that axis's. A value without a unit (the old
  // m/s and N scripts) is refused. Errors are one line naming the segment.
  [[nodiscard]] static Result<HandScript> parse(const std::string& text);
  [[nodiscard]] static Result<HandScript> parse(const std::string& text, int axis);
  // The segment in force at time t since the script started (kFree after the end).
  [[nodiscard]] HandSegment at(uint64_t t_us) const;
  [[nodiscard]] bool empty() const { return segments_.empty(); }

 private:
  std::vector<HandSegment> segments_;
};

}  // namespace cathbox::emu

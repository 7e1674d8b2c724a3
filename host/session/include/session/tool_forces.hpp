#pragma once
// Every tool's hand force tick by tick, against the box's limits (issue 29, "the feel"): with a
// box per tool (`cathbox session run --box TOOL=WHERE`) each box renders its tool's force, held
// by the hand or not, so each tool's force must stay within the full scale and change by no more
// than the slew between ticks. `cathbox session replay --forces` prints it for a record; the feel
// tests (tests/host/session) check it on the bundled runs.
#include <cstdint>
#include <string>
#include <vector>

#include "session/passive_law.hpp"
#include "session/session.hpp"

namespace cathbox::session {

class ToolForces final : public TickObserver {
 public:
  struct Tool {
    std::string name;
    double peak_mN = 0.0;               // largest |hand force|
    double largest_change_mN = 0.0;     // largest |change| between consecutive ticks
    std::int64_t peak_us = 0, change_us = 0;
    std::int64_t over_slew = 0;         // ticks changing by more than the slew
    std::int64_t over_full_scale = 0;   // ticks above the full scale
    double last_mN = 0.0;
    bool seen = false;
  };
  // The box's limits (PassiveLawLimits' defaults: 5 N, 100 mN a 1 ms tick).
  explicit ToolForces(const PassiveLawLimits& box = {}) : box_(box) {}
  void observe(const TickView& v) override;
  [[nodiscard]] const std::vector<Tool>& tools() const { return tools_; }
  [[nodiscard]] double slew_per_tick_mN() const { return box_.slew_mN_per_ms * box_.tick_ms; }
  [[nodiscard]] double full_scale_mN() const { return box_.full_scale_mN; }
  // A line per tool: its peak and when, its largest change a tick and when, its ticks over the
  // slew and over the full scale.
  [[nodiscard]] std::string format() const;

 private:
  PassiveLawLimits box_;
  std::vector<Tool> tools_;
};

}  // namespace cathbox::session

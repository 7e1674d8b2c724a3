#pragma once
// Every tool's hand force tick by tick, against the box's limits (issue 29, "the feel"): with a
// box per tool (`cathbox session run --box TOOL=WHERE`) each box renders its tool's force, held
// by the hand or not, so each tool's force must stay within the full scale and change by no more
// than the slew between ticks. With one box, it renders the held tool's force: `held()` follows
// whichever tool the hand holds, a change counted only between two ticks of the same tool (a tool
// taken up, or a coil loaded on a new pusher, starts afresh). `cathbox session replay --forces`
// prints both for a record; the feel tests (tests/host/session) check them on the bundled runs.
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
  // The held tool's force as one box renders it (Tool's figures; `name` unused).
  struct Held : Tool {
    std::size_t tool = 0;  // the tool held at the last tick
    bool fresh = true;     // that tick started afresh (the first, another tool, a coil loaded)
  };
  // The box's limits (PassiveLawLimits' defaults: 5 N, 100 mN a 1 ms tick).
  explicit ToolForces(const PassiveLawLimits& box = {}) : box_(box) {}
  void observe(const TickView& v) override;
  [[nodiscard]] const std::vector<Tool>& tools() const { return tools_; }
  [[nodiscard]] const Held& held() const { return held_; }
  // Changes a tick counted from `time_us` of the run on (a run's figures from one phase on).
  void count_changes_from(std::int64_t time_us) { changes_from_us_ = time_us; }
  [[nodiscard]] double slew_per_tick_mN() const { return box_.slew_mN_per_ms * box_.tick_ms; }
  [[nodiscard]] double full_scale_mN() const { return box_.full_scale_mN; }
  // A line per tool: its peak and when, its largest change a tick and when, its ticks over the
  // slew and over the full scale; then the same of the held tool (`held`).
  [[nodiscard]] std::string format() const;

 private:
  // One tick of a force against the box's limits; `fresh`: no change counted from the last tick.
  void count(Tool& k, double f, std::int64_t time_us, bool fresh) const;
  PassiveLawLimits box_;
  std::vector<Tool> tools_;
  Held held_;
  std::int64_t changes_from_us_ = 0;
};

}  // namespace cathbox::session

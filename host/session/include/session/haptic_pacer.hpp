#pragma once
// Deadline bookkeeping for a fixed-rate loop, free of any clock: the caller passes the present
// time and learns how many ticks are due. When the loop falls behind by more than
// `max_catch_up` ticks (a stall), the excess ticks are dropped and counted instead of being run
// in a burst, so the simulation never races to catch up with wall time.
#include <cstdint>

namespace cathbox::session {

class HapticPacer {
 public:
  HapticPacer(std::int64_t period_us, std::int64_t start_us, int max_catch_up = 4);

  struct Due {
    int ticks = 0;             // ticks to run now (0 .. max_catch_up)
    std::int64_t dropped = 0;  // ticks skipped by this call because the loop fell behind
  };
  [[nodiscard]] Due due(std::int64_t now_us);

  [[nodiscard]] std::int64_t next_deadline_us() const { return next_us_; }
  [[nodiscard]] std::int64_t period_us() const { return period_us_; }
  [[nodiscard]] std::int64_t dropped_total() const { return dropped_total_; }

 private:
  std::int64_t period_us_;
  std::int64_t next_us_;
  int max_catch_up_;
  std::int64_t dropped_total_ = 0;
};

}  // namespace cathbox::session

#pragma once
// Events per second over a sliding window, fed with timestamps (virtual or real).
#include <cstdint>

namespace cathbox::session {

class RateMeter {
 public:
  explicit RateMeter(std::int64_t window_us = 500'000) : window_us_(window_us) {}

  // Records one event at `now_us`; the rate is refreshed once a window has elapsed.
  void tick(std::int64_t now_us);
  [[nodiscard]] double rate_hz() const { return rate_hz_; }
  [[nodiscard]] std::int64_t count() const { return total_; }

 private:
  std::int64_t window_us_;
  std::int64_t window_start_us_ = -1;
  std::int64_t in_window_ = 0;
  std::int64_t total_ = 0;
  double rate_hz_ = 0.0;
};

}  // namespace cathbox::session

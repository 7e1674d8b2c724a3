#include "session/rate_meter.hpp"

namespace cathbox::session {

void RateMeter::tick(std::int64_t now_us) {
  ++total_;
  if (window_start_us_ < 0) {
    window_start_us_ = now_us;
    return;
  }
  ++in_window_;
  const std::int64_t span = now_us - window_start_us_;
  if (span >= window_us_) {
    rate_hz_ = static_cast<double>(in_window_) * 1e6 / static_cast<double>(span);
    window_start_us_ = now_us;
    in_window_ = 0;
  }
}

}  // namespace cathbox::session

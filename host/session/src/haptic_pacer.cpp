#include "session/haptic_pacer.hpp"

#include <algorithm>

namespace cathbox::session {

HapticPacer::HapticPacer(std::int64_t period_us, std::int64_t start_us, int max_catch_up)
    : period_us_(std::max<std::int64_t>(1, period_us)),
      next_us_(start_us),
      max_catch_up_(std::max(1, max_catch_up)) {}

HapticPacer::Due HapticPacer::due(std::int64_t now_us) {
  Due d;
  if (now_us < next_us_) return d;
  const std::int64_t late = (now_us - next_us_) / period_us_ + 1;  // ticks whose deadline passed
  if (late > max_catch_up_) {
    d.dropped = late - max_catch_up_;
    dropped_total_ += d.dropped;
    next_us_ += d.dropped * period_us_;
  }
  d.ticks = static_cast<int>(std::min<std::int64_t>(late, max_catch_up_));
  next_us_ += static_cast<std::int64_t>(d.ticks) * period_us_;
  return d;
}

}  // namespace cathbox::session

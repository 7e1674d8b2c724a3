#include <poll.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "device/clock.hpp"

namespace cathbox::device {

std::int64_t SystemClock::now_us() {
  const auto t = std::chrono::steady_clock::now().time_since_epoch();
  return std::chrono::duration_cast<std::chrono::microseconds>(t).count();
}

void SystemClock::wait(int fd, std::int64_t max_us) {
  max_us = std::max<std::int64_t>(max_us, 0);
  if (fd < 0) {
    std::this_thread::sleep_for(std::chrono::microseconds(max_us));
    return;
  }
  pollfd p{fd, POLLIN, 0};
  // poll() has millisecond resolution: round up so short waits still wait.
  const int timeout_ms = static_cast<int>((max_us + 999) / 1000);
  (void)::poll(&p, 1, timeout_ms);
}

void SystemClock::sleep_until_us(std::int64_t deadline_us) {
  // The kernel's timer slack is ~50 us; sleep to just before the deadline, then yield-spin.
  constexpr std::int64_t kSpin_us = 80;
  const std::int64_t now = now_us();
  if (deadline_us - now > kSpin_us) {
    std::this_thread::sleep_for(std::chrono::microseconds(deadline_us - now - kSpin_us));
  }
  while (now_us() < deadline_us) std::this_thread::yield();
}

}  // namespace cathbox::device

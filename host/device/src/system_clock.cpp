#include <poll.h>

#include <chrono>
#include <thread>

#include "device/clock.hpp"

namespace cathbox::device {

uint64_t SystemClock::now_us() {
  const auto t = std::chrono::steady_clock::now().time_since_epoch();
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(t).count());
}

void SystemClock::wait(int fd, uint64_t max_us) {
  if (fd < 0) {
    std::this_thread::sleep_for(std::chrono::microseconds(max_us));
    return;
  }
  pollfd p{fd, POLLIN, 0};
  // poll() has millisecond resolution: round up so short waits still wait.
  const int timeout_ms = static_cast<int>((max_us + 999) / 1000);
  (void)::poll(&p, 1, timeout_ms);
}

}  // namespace cathbox::device

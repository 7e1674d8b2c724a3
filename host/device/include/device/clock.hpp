#pragma once
// The one time source of the host: everything that waits (device I/O, flashing, the CLI's
// polls) or paces (the haptic loop in host/session) takes a Clock. SystemClock is the machine's
// monotonic clock; a virtual clock (session::VirtualClock, the emulator world of the tests)
// advances simulated time instead of sleeping, so the same code runs deterministically.
#include <cstdint>

namespace cathbox::device {

class Clock {
 public:
  virtual ~Clock() = default;
  // Monotonic time in microseconds.
  [[nodiscard]] virtual std::int64_t now_us() = 0;
  // Waits at most max_us for fd to become readable (fd < 0: just waits).
  virtual void wait(int fd, std::int64_t max_us) = 0;
  // Returns at deadline_us (at once when it has passed).
  virtual void sleep_until_us(std::int64_t deadline_us) {
    const std::int64_t now = now_us();
    if (deadline_us > now) wait(-1, deadline_us - now);
  }
};

// The monotonic system clock; wait() is poll(2); sleep_until_us() sleeps to just before the
// deadline and then yield-spins, so a 1 kHz loop keeps its period.
class SystemClock final : public Clock {
 public:
  [[nodiscard]] std::int64_t now_us() override;
  void wait(int fd, std::int64_t max_us) override;
  void sleep_until_us(std::int64_t deadline_us) override;
};

}  // namespace cathbox::device

#pragma once
// Time source for everything in host/device that waits: a real clock on a rig, a virtual clock
// (which advances the emulator instead of sleeping) in tests.
#include <cstdint>

namespace cathbox::device {

class Clock {
 public:
  virtual ~Clock() = default;
  // Monotonic time in microseconds.
  [[nodiscard]] virtual uint64_t now_us() = 0;
  // Waits at most max_us for fd to become readable (fd < 0: just waits). A virtual clock
  // advances simulated time instead, so waiting is deterministic.
  virtual void wait(int fd, uint64_t max_us) = 0;
};

// The monotonic system clock; wait() is poll(2).
class SystemClock final : public Clock {
 public:
  [[nodiscard]] uint64_t now_us() override;
  void wait(int fd, uint64_t max_us) override;
};

}  // namespace cathbox::device

#pragma once
// Time for the haptic loop: the host's one Clock (device/clock.hpp). device::SystemClock paces
// against the machine's monotonic clock; VirtualClock jumps straight to each deadline, so the
// same loop runs deterministically and as fast as the CPU allows (tests, and the headless run
// without a display).
#include <atomic>
#include <cstdint>

#include "device/clock.hpp"

namespace cathbox::session {

using device::Clock;

class VirtualClock final : public Clock {
 public:
  explicit VirtualClock(std::int64_t start_us = 0) : now_(start_us) {}
  [[nodiscard]] std::int64_t now_us() override { return now_.load(std::memory_order_acquire); }
  void sleep_until_us(std::int64_t deadline_us) override;
  // Waiting is moving time forward by max_us (no file descriptor ever becomes readable).
  void wait(int /*fd*/, std::int64_t max_us) override { sleep_until_us(now_us() + max_us); }
  // Moves time forward by `us` (a stall, as seen by the loop).
  void advance_us(std::int64_t us) { now_.fetch_add(us, std::memory_order_acq_rel); }

 private:
  std::atomic<std::int64_t> now_;
};

// CPU time used so far by the calling thread, and by the whole process (CLOCK_*_CPUTIME_ID).
[[nodiscard]] std::int64_t thread_cpu_time_us();
[[nodiscard]] std::int64_t process_cpu_time_us();

}  // namespace cathbox::session

#include "session/clock.hpp"

#include <time.h>

#include <chrono>
#include <thread>

namespace cathbox::session {

std::int64_t SteadyClock::now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void SteadyClock::sleep_until_us(std::int64_t deadline_us) {
  // The kernel's timer slack is ~50 us; sleep to just before the deadline, then yield-spin.
  constexpr std::int64_t kSpinUs = 80;
  const std::int64_t now = now_us();
  if (deadline_us - now > kSpinUs) {
    std::this_thread::sleep_for(std::chrono::microseconds(deadline_us - now - kSpinUs));
  }
  while (now_us() < deadline_us) std::this_thread::yield();
}

void VirtualClock::sleep_until_us(std::int64_t deadline_us) {
  std::int64_t now = now_.load(std::memory_order_acquire);
  while (now < deadline_us &&
         !now_.compare_exchange_weak(now, deadline_us, std::memory_order_acq_rel)) {
  }
}

namespace {
std::int64_t cpu_time_us(clockid_t which) {
  timespec ts{};
  clock_gettime(which, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1000;
}
}  // namespace

std::int64_t thread_cpu_time_us() { return cpu_time_us(CLOCK_THREAD_CPUTIME_ID); }
std::int64_t process_cpu_time_us() { return cpu_time_us(CLOCK_PROCESS_CPUTIME_ID); }

}  // namespace cathbox::session

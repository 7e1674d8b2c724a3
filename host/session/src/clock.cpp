#include "session/clock.hpp"

#include <time.h>


namespace cathbox::session {

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

#include <chrono>

#include "server/clock.hpp"

namespace cathbox::server {

std::int64_t SystemClock::now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace cathbox::server

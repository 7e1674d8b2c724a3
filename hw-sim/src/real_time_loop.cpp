#include "emu/real_time_loop.hpp"

#include <poll.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace cathbox::emu {
namespace {
uint64_t wall_us() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}
}  // namespace

void RealTimeLoop::run(Emulator& emu, const std::atomic<bool>& stop, uint64_t duration_us,
                       const std::function<void(uint64_t)>& each) {
  const uint64_t start = wall_us() - emu.now_us();
  const uint64_t end = duration_us > 0 ? emu.now_us() + duration_us : UINT64_MAX;
  std::vector<pollfd> fds;
  while (!stop.load(std::memory_order_relaxed)) {
    const uint64_t now = wall_us() - start;
    if (now >= end) break;
    if (each) each(emu.now_us());
    // Catch up with the wall clock in whole physics steps (at most 100 ms at a time).
    if (now >= emu.now_us() + Emulator::kPhysicsStep_us) {
      const uint64_t behind = now - emu.now_us();
      emu.advance(std::min<uint64_t>(behind - behind % Emulator::kPhysicsStep_us, 100'000));
      continue;
    }
    // Sleep until the next physics step is due or socket input arrives.
    fds.clear();
    if (emu.server() != nullptr) {
      for (const int fd : emu.server()->fds()) fds.push_back({fd, POLLIN, 0});
    }
    const uint64_t due = emu.now_us() + Emulator::kPhysicsStep_us;
    const uint64_t next_frame = (emu.now_us() / Emulator::kFrame_us + 1) * Emulator::kFrame_us;
    const uint64_t wake = std::max(due, std::min(next_frame, due + Emulator::kFrame_us));
    const uint64_t wait_us = wake > now ? wake - now : 0;
    timespec timeout{0, static_cast<long>(wait_us * 1000)};
    if (::ppoll(fds.data(), fds.size(), &timeout, nullptr) > 0) emu.service();
  }
}

}  // namespace cathbox::emu

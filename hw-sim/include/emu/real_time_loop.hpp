#pragma once
// Runs an Emulator against the wall clock: simulated time follows the monotonic clock, socket
// input is handled as soon as it arrives, and the thread sleeps in ppoll between frames.
// Used by the cathbox-emu executable and by bench/device.
#include <poll.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <vector>

#include "emu/emulator.hpp"

namespace cathbox::emu {

class RealTimeLoop {
 public:
  // Runs until `stop` is set or duration_us of wall time passed (0: no limit). `each`, if
  // given, is called once per iteration with the simulated time (scripted events).
  static void run(Emulator& emu, const std::atomic<bool>& stop, uint64_t duration_us,
                  const std::function<void(uint64_t now_us)>& each = {});
  // The same for any box with advance(us), service(), now_us() and server() (ImageEmulator).
  template <class Box>
  static void run_box(Box& emu, const std::atomic<bool>& stop, uint64_t duration_us,
                      const std::function<void(uint64_t now_us)>& each);
};

template <class Box>
void RealTimeLoop::run_box(Box& emu, const std::atomic<bool>& stop, uint64_t duration_us,
                           const std::function<void(uint64_t)>& each) {
  constexpr uint64_t kStep_us = Emulator::kPhysicsStep_us;
  constexpr uint64_t kFrame_us = Emulator::kFrame_us;
  auto wall_us = [] {
    return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                     std::chrono::steady_clock::now().time_since_epoch())
                                     .count());
  };
  const uint64_t start = wall_us() - emu.now_us();
  const uint64_t end = duration_us > 0 ? emu.now_us() + duration_us : UINT64_MAX;
  std::vector<pollfd> fds;
  while (!stop.load(std::memory_order_relaxed)) {
    const uint64_t now = wall_us() - start;
    if (now >= end) {  // the run's virtual time is completed even if the process fell behind
      const uint64_t left = end > emu.now_us() ? end - emu.now_us() : 0;
      emu.advance(left - left % kStep_us);
      break;
    }
    if (each) each(emu.now_us());
    // Catch up with the wall clock in whole physics steps (at most 100 ms at a time).
    if (now >= emu.now_us() + kStep_us) {
      const uint64_t behind = now - emu.now_us();
      emu.advance(std::min<uint64_t>(behind - behind % kStep_us, 100'000));
      continue;
    }
    // Sleep until the next physics step is due or socket input arrives.
    fds.clear();
    if (emu.server() != nullptr) {
      for (const int fd : emu.server()->fds()) fds.push_back({fd, POLLIN, 0});
    }
    const uint64_t due = emu.now_us() + kStep_us;
    const uint64_t next_frame = (emu.now_us() / kFrame_us + 1) * kFrame_us;
    const uint64_t wake = std::max(due, std::min(next_frame, due + kFrame_us));
    const uint64_t wait_us = wake > now ? wake - now : 0;
    timespec timeout{0, static_cast<long>(wait_us * 1000)};
    if (::ppoll(fds.data(), fds.size(), &timeout, nullptr) > 0) emu.service();
  }
}

}  // namespace cathbox::emu

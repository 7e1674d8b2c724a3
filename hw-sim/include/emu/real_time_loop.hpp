#pragma once
// Runs an Emulator against the wall clock: simulated time follows the monotonic clock, socket
// input is handled as soon as it arrives, and the thread sleeps in ppoll between frames.
// Used by the cathbox-emu executable and by bench/device.
#include <atomic>
#include <cstdint>
#include <functional>

#include "emu/emulator.hpp"

namespace cathbox::emu {

class RealTimeLoop {
 public:
  // Runs until `stop` is set or duration_us of wall time passed (0: no limit). `each`, if
  // given, is called once per iteration with the simulated time (scripted events).
  static void run(Emulator& emu, const std::atomic<bool>& stop, uint64_t duration_us,
                  const std::function<void(uint64_t now_us)>& each = {});
};

}  // namespace cathbox::emu

#pragma once
// The simulated board behind firmware/hal's port contract: what cbx_hal_* read and write when
// firmware/core runs inside cathbox-emu. The emulator makes one board current (per thread)
// while it runs the core; the C functions of cbx_hal.h act on that board.
#include <array>
#include <cstdint>
#include <vector>

namespace cathbox::emu {

struct SimBoard {
  uint64_t time_us = 0;                      // board clock (cbx_hal_time_us wraps it to 32 bits)
  std::array<uint32_t, 2> counter{};         // hardware counters (unused with the edge source)
  std::array<int16_t, 2> current_mA{};       // current sense, set by the physical model
  std::array<int16_t, 2> drive_permille{};   // actuator drive, set by the core
  bool estop_pressed = false;
  uint16_t supply_mV = 12000;
  bool led = false;
  uint64_t watchdog_kicks = 0;
  bool bootloader_requested = false;
  std::vector<uint8_t> store;                // persisted settings (empty: none)
  uint64_t store_saves = 0;

  // Makes this board the one cbx_hal_* act on (for the calling thread) until the guard ends.
  class Current {
   public:
    explicit Current(SimBoard& board);
    ~Current();
    Current(const Current&) = delete;
    Current& operator=(const Current&) = delete;

   private:
    SimBoard* previous_;
  };
};

}  // namespace cathbox::emu

#pragma once
// The two MCU pins a lab-rig host drives to recover a board that no longer enumerates: BOOT0
// (high at reset = start the ROM bootloader) and NRST (active low reset, open drain).
#include <cstdint>
#include <string>

#include "device/result.hpp"

namespace cathbox::device {

class BootPins {
 public:
  virtual ~BootPins() = default;
  // BOOT0 level: true = high (ROM bootloader on the next reset).
  [[nodiscard]] virtual Status set_boot0(bool high) = 0;
  // true = hold the MCU in reset (NRST pulled low); false = release (line floats high).
  [[nodiscard]] virtual Status set_reset(bool asserted) = 0;
  virtual void delay(uint64_t us) = 0;
};

// Recovery sequences over any BootPins.
class BootRecovery {
 public:
  // BOOT0 high, reset pulse: the MCU starts the ROM DFU bootloader (0483:DF11). BOOT0 stays
  // high until run_application() so a reset during flashing returns to the bootloader.
  [[nodiscard]] static Status enter_bootloader(BootPins& pins);
  // BOOT0 low, reset pulse: the MCU starts the application from flash.
  [[nodiscard]] static Status run_application(BootPins& pins);
  static constexpr uint64_t kResetPulse_us = 10'000;   // NRST low
  static constexpr uint64_t kBootWait_us = 100'000;    // after release, before USB is expected
};

}  // namespace cathbox::device

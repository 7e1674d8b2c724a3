#include "device/boot_pins.hpp"

namespace cathbox::device {
namespace {

Status pulse_reset(BootPins& pins) {
  if (auto held = pins.set_reset(true); !held) return held;
  pins.delay(BootRecovery::kResetPulse_us);
  if (auto released = pins.set_reset(false); !released) return released;
  pins.delay(BootRecovery::kBootWait_us);
  return Ok{};
}

}  // namespace

Status BootRecovery::enter_bootloader(BootPins& pins) {
  if (auto boot0 = pins.set_boot0(true); !boot0) return boot0;
  return pulse_reset(pins);
}

Status BootRecovery::run_application(BootPins& pins) {
  if (auto boot0 = pins.set_boot0(false); !boot0) return boot0;
  return pulse_reset(pins);
}

}  // namespace cathbox::device

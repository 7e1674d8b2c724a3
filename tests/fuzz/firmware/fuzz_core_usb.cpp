// libFuzzer target: arbitrary bytes as an interrupt OUT report and as a feature SET_REPORT to
// a calibrated, running core, then control ticks. Properties: never crash; the actuator drive
// stays within +-1000 per mille; the rendered force and torque stay within the limits in
// force; brake mode never drives along the motion; every state report the core produces
// decodes; every feature report it answers with passes the protocol's checks.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "../fuzz_crc_fix.hpp"

extern "C" {
#include "fake_hal.h"
}

namespace {
cbx_core core;

void check_tick() {
  cbx_fake.time_us += CBX_CORE_TICK_US;
  cbx_fake.counter[0] += 7u;
  cbx_fake.counter[1] -= 3u;
  cbx_core_control_tick(&core);
  for (int i = 0; i < CBX_AXIS_COUNT; ++i)
    if (cbx_fake.drive[i] > 1000 || cbx_fake.drive[i] < -1000) std::abort();
  cbx_state_report s;
  cbx_core_state(&core, &s);
  const cbx_settings& limits = core.settings;
  if (s.insertion_force_mN > static_cast<int64_t>(limits.limits.max_force_mN) ||
      -static_cast<int64_t>(s.insertion_force_mN) > static_cast<int64_t>(limits.limits.max_force_mN))
    std::abort();
  if (s.rotation_torque_uNm > static_cast<int64_t>(limits.limits.max_torque_uNm) ||
      -static_cast<int64_t>(s.rotation_torque_uNm) > static_cast<int64_t>(limits.limits.max_torque_uNm))
    std::abort();
  // Brake mode only resists: the drive never has the sign of the motion (a motor renders
  // brake mode with the force's sign, a brake gets the magnitude).
  if (s.mode == CBX_MODE_BRAKE && !(s.status & CBX_STATUS_SELFTEST_RUNNING)) {
    if (s.insertion_vel_cps > 0 && cbx_fake.drive[0] > 0) std::abort();
    if (s.rotation_vel_cps < 0 && cbx_fake.drive[1] < 0) std::abort();
  }
  uint8_t report[CBX_REPORT_SIZE];
  if (cbx_core_usb_in_report(&core, report)) {
    cbx_state_report decoded;
    if (cbx_state_decode(report, sizeof report, &decoded) != CBX_OK) std::abort();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* input, size_t size) {
  uint8_t fixed[CBX_REPORT_SIZE];
  const uint8_t* data = cbx_fuzz_fix_crc(input, size, fixed);
  cbx_fake_reset();
  const cbx_core_config config = cbx_fake_config(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR);
  cbx_core_init(&core, &config);
  cbx_fake_calibrate(&core);
  const cbx_force_law push = cbx_fake_constant_law(3000, 40000);
  (void)cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &push, &push);
  for (int i = 0; i < 20; ++i) check_tick();

  (void)cbx_core_usb_out_report(&core, data, size);
  for (int i = 0; i < 20; ++i) check_tick();
  (void)cbx_core_usb_feature_set(&core, data, size);
  for (int i = 0; i < 20; ++i) check_tick();
  if (size > 0) {
    uint8_t report[CBX_REPORT_SIZE];
    if (cbx_core_usb_feature_get(&core, data[0], report) == CBX_OK &&
        cbx_report_check(report, sizeof report, data[0]) != CBX_OK)
      std::abort();
  }
  return 0;
}

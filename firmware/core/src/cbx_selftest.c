#include "cbx_core_internal.h"

void cbx_selftest_start(cbx_core* core, uint32_t now_us) {
  cbx_selftest_run* t = &core->selftest;
  t->state = CBX_SELFTEST_RUNNING;
  t->phase = 0u;
  t->phase_start_us = now_us;
  for (int i = 0; i < CBX_AXIS_COUNT; ++i) t->errors_at_start[i] = core->encoder[i].errors;
  t->result.state = CBX_SELFTEST_RUNNING;
  t->result.failed_checks = 0u;
  t->result.insertion_current_mA = 0;
  t->result.rotation_current_mA = 0;
  t->result.supply_mV = 0u;
}

static bool current_ok(int16_t mA, uint16_t limit_mA) {
  const int32_t c = mA < 0 ? -(int32_t)mA : mA;
  return c >= CBX_SELFTEST_MIN_CURRENT_MA && c <= (int32_t)limit_mA;
}

/* Phases: 0 drives the insertion actuator, 1 the rotation actuator, each for 20 ms with the
 * current sampled at the end; then the checks are evaluated. */
bool cbx_selftest_tick(cbx_core* core, uint32_t now_us, bool estop_pressed,
                       const int16_t current_mA[CBX_AXIS_COUNT]) {
  cbx_selftest_run* t = &core->selftest;
  if (t->state != CBX_SELFTEST_RUNNING) return false;
  cbx_selftest* r = &t->result;
  if (estop_pressed) {
    r->failed_checks |= CBX_CHECK_ESTOP;
    t->phase = CBX_AXIS_COUNT;
  }
  if (t->phase < CBX_AXIS_COUNT && now_us - t->phase_start_us >= CBX_SELFTEST_PHASE_US) {
    const cbx_axis axis = (cbx_axis)t->phase;
    const uint16_t limit = axis == CBX_AXIS_INSERTION ? core->settings.limits.insertion_max_current_mA
                                                      : core->settings.limits.rotation_max_current_mA;
    if (axis == CBX_AXIS_INSERTION) r->insertion_current_mA = current_mA[axis];
    else r->rotation_current_mA = current_mA[axis];
    if (core->config.axis[axis].actuator != CBX_ACTUATOR_NONE && !current_ok(current_mA[axis], limit))
      r->failed_checks |= axis == CBX_AXIS_INSERTION ? CBX_CHECK_INSERTION_ACTUATOR
                                                     : CBX_CHECK_ROTATION_ACTUATOR;
    t->phase++;
    t->phase_start_us = now_us;
  }
  for (int i = 0; i < CBX_AXIS_COUNT; ++i) {
    const bool on = t->phase == (uint8_t)i && core->config.axis[i].actuator != CBX_ACTUATOR_NONE;
    core->drive[i] = on ? CBX_SELFTEST_DRIVE_PERMILLE : 0;
    core->out[i] = 0;
  }
  if (t->phase < CBX_AXIS_COUNT) return true;

  if (core->encoder[CBX_AXIS_INSERTION].errors != t->errors_at_start[CBX_AXIS_INSERTION])
    r->failed_checks |= CBX_CHECK_INSERTION_ENCODER;
  if (core->encoder[CBX_AXIS_ROTATION].errors != t->errors_at_start[CBX_AXIS_ROTATION])
    r->failed_checks |= CBX_CHECK_ROTATION_ENCODER;
  if (!core->scale[CBX_AXIS_INSERTION].valid || !core->scale[CBX_AXIS_ROTATION].valid)
    r->failed_checks |= CBX_CHECK_CALIBRATION;
  r->supply_mV = cbx_hal_supply_mV();
  t->state = r->failed_checks ? CBX_SELFTEST_FAILED : CBX_SELFTEST_PASSED;
  r->state = t->state;
  if (t->state == CBX_SELFTEST_PASSED) r->failed_checks = 0u;
  return true;
}

void cbx_selftest_abort(cbx_core* core, uint16_t checks) {
  cbx_selftest_run* t = &core->selftest;
  t->state = CBX_SELFTEST_FAILED;
  t->result.state = CBX_SELFTEST_FAILED;
  t->result.failed_checks |= checks;
  for (int i = 0; i < CBX_AXIS_COUNT; ++i) core->drive[i] = 0;
}

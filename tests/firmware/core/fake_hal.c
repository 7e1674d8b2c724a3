#include "fake_hal.h"

#include <string.h>

#include "cbx_test.h"

cbx_fake_board cbx_fake;

void cbx_fake_reset(void) {
  memset(&cbx_fake, 0, sizeof cbx_fake);
  cbx_fake.supply_mV = 12000u;
}

/* The port contract, on the fake board. */
uint32_t cbx_hal_time_us(void) { return cbx_fake.time_us; }
uint32_t cbx_hal_encoder_counter(cbx_axis axis) { return cbx_fake.counter[axis]; }
int16_t cbx_hal_current_mA(cbx_axis axis) {
  if (cbx_fake.mA_per_permille) return (int16_t)(cbx_fake.drive[axis] * cbx_fake.mA_per_permille);
  return cbx_fake.current_mA[axis];
}
bool cbx_hal_estop_pressed(void) { return cbx_fake.estop; }
void cbx_hal_actuator_set(cbx_axis axis, int16_t drive_permille) {
  cbx_fake.drive[axis] = drive_permille;
  cbx_fake.actuator_calls++;
}
uint16_t cbx_hal_supply_mV(void) { return cbx_fake.supply_mV; }
void cbx_hal_led_set(bool on) { cbx_fake.led = on; }
void cbx_hal_watchdog_kick(void) { cbx_fake.kicks++; }
void cbx_hal_bootloader_request(void) { cbx_fake.bootloader_requests++; }
bool cbx_hal_store_load(void* data, size_t size) {
  if (cbx_fake.store_size != size) return false;
  memcpy(data, cbx_fake.store, size);
  return true;
}
bool cbx_hal_store_save(const void* data, size_t size) {
  if (size > sizeof cbx_fake.store) return false;
  memcpy(cbx_fake.store, data, size);
  cbx_fake.store_size = size;
  cbx_fake.saves++;
  return true;
}

cbx_core_config cbx_fake_config(cbx_encoder_source source, cbx_actuator actuator) {
  cbx_core_config c;
  memset(&c, 0, sizeof c);
  strcpy(c.serial, "CBX-0001");
  strcpy(c.board, "fake");
  c.fw_version[0] = CBX_FW_MAJOR;
  c.fw_version[1] = CBX_FW_MINOR;
  c.fw_version[2] = CBX_FW_PATCH;
  strcpy(c.build, "test");
  for (int i = 0; i < CBX_AXIS_COUNT; ++i) {
    c.axis[i].encoder_source = (uint8_t)source;
    c.axis[i].counter_bits = 16u;
    c.axis[i].actuator = (uint8_t)actuator;
    c.axis[i].encoder_cpr = 2400u;
  }
  return c;
}

void cbx_fake_tick(cbx_core* core) {
  cbx_fake.time_us += CBX_CORE_TICK_US;
  cbx_core_control_tick(core);
}

void cbx_fake_run_us(cbx_core* core, uint32_t us) {
  for (uint32_t t = 0; t < us; t += CBX_CORE_TICK_US) cbx_fake_tick(core);
}

cbx_status cbx_fake_command(cbx_core* core, uint8_t mode, uint8_t flags, const cbx_force_law* insertion,
                            const cbx_force_law* rotation) {
  static uint16_t seq;
  cbx_command_report c;
  memset(&c, 0, sizeof c);
  c.header.version = CBX_PROTOCOL_VERSION;
  c.header.seq = ++seq;
  c.header.time_us = cbx_fake.time_us;
  c.mode = mode;
  c.flags = flags;
  if (insertion) c.insertion = *insertion;
  if (rotation) c.rotation = *rotation;
  uint8_t bytes[CBX_REPORT_SIZE];
  const cbx_status st = cbx_command_encode(&c, bytes);
  CBX_CHECK_EQ(st, CBX_OK);
  return cbx_core_usb_out_report(core, bytes, sizeof bytes);
}

const cbx_vector* cbx_fake_vector(const char* name) {
  for (size_t i = 0; i < cbx_vector_count; ++i)
    if (strcmp(cbx_vectors[i].name, name) == 0) return &cbx_vectors[i];
  cbx_test_fail(__FILE__, __LINE__, "no golden vector %s", name);
  return NULL;
}

void cbx_fake_calibrate(cbx_core* core) {
  const cbx_vector* v = cbx_fake_vector("calibration_identity");
  if (v) CBX_CHECK_EQ(cbx_core_usb_feature_set(core, v->bytes, v->length), CBX_OK);
}

cbx_force_law cbx_fake_constant_law(int32_t out, int32_t limit) {
  cbx_force_law law;
  memset(&law, 0, sizeof law);
  law.offset = out;
  law.out_min = -limit;
  law.out_max = limit;
  return law;
}

cbx_state_report cbx_fake_state(cbx_core* core) {
  cbx_state_report r;
  cbx_core_state(core, &r);
  return r;
}

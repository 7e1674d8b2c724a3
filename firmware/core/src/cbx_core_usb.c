/* Protocol v1 handling: interrupt OUT commands, interrupt IN state reports and the feature
 * reports on the control endpoint. Runs in the USB context; hands data to the control tick
 * through the two-slot mailboxes of cbx_core. */
#include <string.h>

#include "cbx_core_internal.h"

static void count_rx_error(cbx_core* core) {
  if (core->rx_errors != UINT32_MAX) core->rx_errors++;
}

static cbx_header next_header(uint16_t* seq) {
  cbx_header h;
  h.version = CBX_PROTOCOL_VERSION;
  h.seq = ++*seq;
  h.time_us = cbx_hal_time_us();
  return h;
}

cbx_status cbx_core_usb_out_report(cbx_core* core, const uint8_t* data, size_t length) {
  const uint8_t slot = (uint8_t)(core->command_published ^ 1u);
  const cbx_status st = cbx_command_decode(data, length, &core->command_slot[slot]);
  if (st != CBX_OK) {
    count_rx_error(core);
    core->bad_command_count++;
    return st;
  }
  /* Sticky until the tick takes it: a newer command before the next tick must not drop it. */
  if (core->command_slot[slot].flags & CBX_CMD_ACK_FAULTS) core->ack_pending = 1u;
  CBX_COMPILER_BARRIER(); /* the slot is complete before it is published */
  core->command_published = slot;
  core->command_generation++;
  return CBX_OK;
}

void cbx_core_usb_reset(cbx_core* core) {
  const uint8_t slot = (uint8_t)(core->command_published ^ 1u);
  cbx_command_report* c = &core->command_slot[slot];
  /* Not a command of the host: the seq echoed stays that of its last one. */
  const uint16_t seq = core->command_slot[core->command_published].header.seq;
  memset(c, 0, sizeof *c);
  c->header.version = CBX_PROTOCOL_VERSION;
  c->header.seq = seq;
  c->mode = CBX_MODE_OFF;
  CBX_COMPILER_BARRIER(); /* the slot is complete before it is published */
  core->command_published = slot;
  core->command_generation++;
}

void cbx_core_usb_in_dropped(cbx_core* core) {
  if (core->in_dropped != UINT32_MAX) core->in_dropped++;
}

/* The next state report: the tick's snapshot plus what the USB context counts. */
static cbx_status state_report(cbx_core* core, uint8_t out[CBX_REPORT_SIZE]) {
  cbx_state_report r;
  cbx_core_state(core, &r);
  r.header.seq = ++core->in_seq;
  r.in_dropped = core->in_dropped > 0xFFFFu ? 0xFFFFu : (uint16_t)core->in_dropped;
  return cbx_state_encode(&r, out);
}

bool cbx_core_usb_in_report(cbx_core* core, uint8_t out[CBX_REPORT_SIZE]) {
  const uint32_t ms = core->snapshot_ms;
  if (ms == core->reported_ms) return false;
  core->reported_ms = ms;
  return state_report(core, out) == CBX_OK;
}

static void current_settings(cbx_core* core, cbx_settings* s) {
  *s = core->settings_slot[core->settings_published];
}

static void publish_settings(cbx_core* core, const cbx_settings* s) {
  const uint8_t slot = (uint8_t)(core->settings_published ^ 1u);
  core->settings_slot[slot] = *s;
  cbx_core_scales(&core->settings_slot[slot], core->scale_slot[slot]);
  CBX_COMPILER_BARRIER(); /* the slot is complete before it is published */
  core->settings_published = slot;
  core->settings_generation++;
  core->save_pending = 1u;
}

static cbx_status device_info(cbx_core* core, uint8_t out[CBX_REPORT_SIZE]) {
  cbx_device_info v;
  memset(&v, 0, sizeof v);
  v.header = next_header(&core->feature_seq);
  v.fw_major = core->config.fw_version[0];
  v.fw_minor = core->config.fw_version[1];
  v.fw_patch = core->config.fw_version[2];
  v.protocol_minor = CBX_PROTOCOL_MINOR;
  memcpy(v.serial, core->config.serial, sizeof v.serial);
  memcpy(v.board, core->config.board, sizeof v.board);
  memcpy(v.build, core->config.build, sizeof v.build);
  v.serial[CBX_TEXT_FIELD] = v.board[CBX_TEXT_FIELD] = v.build[CBX_BUILD_FIELD] = '\0';
  v.insertion_actuator = core->config.axis[CBX_AXIS_INSERTION].actuator;
  v.rotation_actuator = core->config.axis[CBX_AXIS_ROTATION].actuator;
  v.insertion_encoder_cpr = core->config.axis[CBX_AXIS_INSERTION].encoder_cpr;
  v.rotation_encoder_cpr = core->config.axis[CBX_AXIS_ROTATION].encoder_cpr;
  return cbx_device_info_encode(&v, out);
}

cbx_status cbx_core_usb_feature_get(cbx_core* core, uint8_t id, uint8_t out[CBX_REPORT_SIZE]) {
  cbx_settings s;
  switch (id) {
    case CBX_ID_STATE:
      return state_report(core, out);
    case CBX_ID_DEVICE_INFO:
      return device_info(core, out);
    case CBX_ID_CALIBRATION:
      current_settings(core, &s);
      s.calibration.header = next_header(&core->feature_seq);
      return cbx_calibration_encode(&s.calibration, out);
    case CBX_ID_LIMITS:
      current_settings(core, &s);
      s.limits.header = next_header(&core->feature_seq);
      return cbx_limits_encode(&s.limits, out);
    case CBX_ID_SELFTEST: {
      cbx_selftest r;
      CBX_TICK_CONSISTENT(core, r = core->selftest.result);
      r.state = core->selftest.state;
      if (r.state != CBX_SELFTEST_FAILED) r.failed_checks = 0u;
      r.header = next_header(&core->feature_seq);
      return cbx_selftest_encode(&r, out);
    }
    default:
      return CBX_ERR_REPORT_ID;
  }
}

static cbx_status feature_set(cbx_core* core, const uint8_t* data, size_t length) {
  const int id = cbx_report_peek_id(data, length);
  if (id < 0) return (cbx_status)id;
  cbx_settings s;
  cbx_status st;
  switch (id) {
    case CBX_ID_CALIBRATION:
      current_settings(core, &s);
      st = cbx_calibration_decode(data, length, &s.calibration);
      if (st == CBX_OK) publish_settings(core, &s);
      return st;
    case CBX_ID_LIMITS:
      current_settings(core, &s);
      st = cbx_limits_decode(data, length, &s.limits);
      if (st == CBX_OK) publish_settings(core, &s);
      return st;
    case CBX_ID_RESET_COUNTERS: {
      cbx_reset_counters r;
      st = cbx_reset_counters_decode(data, length, &r);
      if (st != CBX_OK) return st;
      /* Not yet taken by the tick: add to the pending mask. */
      const bool pending = core->reset_generation != core->applied_reset_generation;
      core->reset_mask = (uint8_t)(pending ? (core->reset_mask | r.mask) : r.mask);
      CBX_COMPILER_BARRIER();
      core->reset_generation++;
      return CBX_OK;
    }
    case CBX_ID_ENTER_BOOTLOADER: {
      cbx_enter_bootloader b;
      st = cbx_enter_bootloader_decode(data, length, &b);
      if (st != CBX_OK) return st;
      core->bootloader_pending = 1u;
      cbx_hal_bootloader_request();
      return CBX_OK;
    }
    case CBX_ID_SELFTEST: {
      cbx_selftest t;
      st = cbx_selftest_decode(data, length, &t);
      if (st != CBX_OK) return st;
      if (t.state != CBX_SELFTEST_RUNNING) return CBX_ERR_RANGE;
      if (core->gate == CBX_GATE_RUN || core->gate == CBX_GATE_RAMP ||
          core->selftest.state == CBX_SELFTEST_RUNNING)
        return CBX_ERR_STATE;
      core->selftest_generation++;
      return CBX_OK;
    }
    default:
      return CBX_ERR_REPORT_ID;
  }
}

cbx_status cbx_core_usb_feature_set(cbx_core* core, const uint8_t* data, size_t length) {
  if (data == NULL) {
    count_rx_error(core);
    return CBX_ERR_NULL;
  }
  const cbx_status st = feature_set(core, data, length);
  if (st != CBX_OK) count_rx_error(core);
  return st;
}

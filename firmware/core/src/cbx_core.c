#include <string.h>

#include "cbx_core_internal.h"

#define UM_PER_M 1000000ull
#define URAD_PER_REV 6283185ull /* 2*pi*1e6 */

void cbx_core_default_settings(cbx_settings* settings) {
  memset(settings, 0, sizeof *settings);
  cbx_calibration* c = &settings->calibration;
  c->header.version = CBX_PROTOCOL_VERSION;
  for (unsigned i = 0; i < CBX_CURVE_POINTS; ++i) {
    const uint16_t v = (uint16_t)((i + 1u) * CBX_PERMILLE_MAX / CBX_CURVE_POINTS);
    c->insertion_curve[i].in_permille = c->insertion_curve[i].out_permille = v;
    c->rotation_curve[i].in_permille = c->rotation_curve[i].out_permille = v;
  }
  cbx_limits* l = &settings->limits;
  l->header.version = CBX_PROTOCOL_VERSION;
  l->max_force_mN = 5000u;
  l->max_torque_uNm = 50000u;
  l->watchdog_timeout_ms = 50u;
  l->insertion_max_current_mA = 1500u;
  l->rotation_max_current_mA = 1000u;
  l->force_slew_mN_per_ms = 100u;
  l->torque_slew_uNm_per_ms = 1000u;
}

void cbx_core_scales(const cbx_settings* s, cbx_axis_scale scale[CBX_AXIS_COUNT]) {
  const cbx_calibration* c = &s->calibration;
  const cbx_limits* l = &s->limits;
  cbx_axis_scale_set(&scale[CBX_AXIS_INSERTION], c->insertion_counts_per_m, UM_PER_M,
                     c->insertion_full_scale_mN, c->insertion_curve, l->max_force_mN,
                     l->force_slew_mN_per_ms);
  cbx_axis_scale_set(&scale[CBX_AXIS_ROTATION], c->rotation_counts_per_rev, URAD_PER_REV,
                     c->rotation_full_scale_uNm, c->rotation_curve, l->max_torque_uNm,
                     l->torque_slew_uNm_per_ms);
}

/* Takes the published settings and their scales (a copy, no divisions), pointing the curves
 * at the copy in force. */
static void take_settings(cbx_core* core, uint8_t slot) {
  core->settings = core->settings_slot[slot];
  core->scale[CBX_AXIS_INSERTION] = core->scale_slot[slot][CBX_AXIS_INSERTION];
  core->scale[CBX_AXIS_ROTATION] = core->scale_slot[slot][CBX_AXIS_ROTATION];
  core->scale[CBX_AXIS_INSERTION].curve = core->settings.calibration.insertion_curve;
  core->scale[CBX_AXIS_ROTATION].curve = core->settings.calibration.rotation_curve;
}

/* The persisted block: the calibration and limits reports as on the wire (CRC-protected and
 * range-checked again on load). */
#define STORE_SIZE (2u * CBX_REPORT_SIZE)

static void load_settings(cbx_settings* s) {
  cbx_core_default_settings(s);
  uint8_t block[STORE_SIZE];
  if (!cbx_hal_store_load(block, sizeof block)) return;
  cbx_settings loaded;
  if (cbx_calibration_decode(block, CBX_REPORT_SIZE, &loaded.calibration) != CBX_OK) return;
  if (cbx_limits_decode(block + CBX_REPORT_SIZE, CBX_REPORT_SIZE, &loaded.limits) != CBX_OK) return;
  *s = loaded;
}

void cbx_core_init(cbx_core* core, const cbx_core_config* config) {
  memset(core, 0, sizeof *core);
  core->config = *config;
  load_settings(&core->settings);
  core->settings_slot[0] = core->settings;
  cbx_core_scales(&core->settings_slot[0], core->scale_slot[0]);
  core->command_slot[0].mode = CBX_MODE_OFF;
  take_settings(core, 0u);
  const uint32_t now = cbx_hal_time_us();
  for (int i = 0; i < CBX_AXIS_COUNT; ++i) {
    const cbx_axis_config* a = &config->axis[i];
    const uint32_t raw = a->encoder_source == CBX_ENCODER_COUNTER ? cbx_hal_encoder_counter((cbx_axis)i) : 0u;
    cbx_encoder_init(&core->encoder[i], (cbx_encoder_source)a->encoder_source, a->counter_bits, raw, now);
    core->current_cap[i] = CBX_PERMILLE_MAX;
    cbx_hal_actuator_set((cbx_axis)i, 0);
  }
  cbx_safety_init(&core->safety);
  core->last_tick_us = now;
  core->snapshot.status = core->scale[0].valid && core->scale[1].valid ? CBX_STATUS_CALIBRATED : 0u;
  core->snapshot.faults = cbx_safety_faults(&core->safety, core->snapshot.status != 0u);
  core->snapshot.board_faults = config->board_faults;
}

void cbx_core_encoder_edge(cbx_core* core, cbx_axis axis, uint8_t ab) {
  if ((unsigned)axis < CBX_AXIS_COUNT) cbx_encoder_edge(&core->encoder[axis], ab);
}

void cbx_core_encoder_rest(cbx_core* core, cbx_axis axis, uint8_t ab) {
  if ((unsigned)axis < CBX_AXIS_COUNT) cbx_encoder_rest(&core->encoder[axis], ab);
}

/* Takes what the USB context published since the last tick. */
static void apply_mailboxes(cbx_core* core, uint32_t now, const cbx_safety_inputs* in) {
  if (core->settings_generation != core->applied_settings_generation) {
    core->applied_settings_generation = core->settings_generation;
    take_settings(core, core->settings_published);
  }
  if (core->reset_generation != core->applied_reset_generation) {
    core->applied_reset_generation = core->reset_generation;
    const uint8_t mask = core->reset_mask;
    if (mask & CBX_RESET_INSERTION_COUNT) cbx_encoder_zero(&core->encoder[CBX_AXIS_INSERTION]);
    if (mask & CBX_RESET_ROTATION_COUNT) cbx_encoder_zero(&core->encoder[CBX_AXIS_ROTATION]);
    if (mask & CBX_RESET_ERROR_COUNTERS) {
      for (int i = 0; i < CBX_AXIS_COUNT; ++i) core->encoder[i].errors = 0u;
      core->encoder_errors_seen = 0u;
      core->rx_errors = 0u;
    }
  }
  if (core->bad_command_count != core->applied_bad_commands) {
    core->applied_bad_commands = core->bad_command_count;
    cbx_safety_bad_command(&core->safety);
  }
  if (core->command_generation != core->applied_command_generation) {
    core->applied_command_generation = core->command_generation;
    core->command = core->command_slot[core->command_published];
    core->command_seq_echo = core->command.header.seq;
    uint8_t flags = core->command.flags;
    if (core->ack_pending) {
      flags |= CBX_CMD_ACK_FAULTS;
      core->ack_pending = 0u;
    }
    cbx_safety_command(&core->safety, now, core->command.mode, flags, in, &core->settings.limits);
  }
  if (core->selftest_generation != core->applied_selftest_generation) {
    core->applied_selftest_generation = core->selftest_generation;
    cbx_selftest_start(core, now);
  }
}

static int32_t ceil_step(int32_t per_ms, uint32_t dt_us) {
  const int64_t s = ((int64_t)per_ms * dt_us + 999) / 1000;
  return s > INT32_MAX ? INT32_MAX : (int32_t)(s < 1 ? 1 : s);
}

static void render_axis(cbx_core* core, cbx_axis axis, cbx_gate gate, uint32_t dt,
                        int16_t current_mA) {
  const cbx_axis_scale* s = &core->scale[axis];
  const cbx_encoder* e = &core->encoder[axis];
  const uint8_t actuator = core->config.axis[axis].actuator;
  uint8_t mode = core->safety.mode;
  if (mode == CBX_MODE_MOTOR && actuator == CBX_ACTUATOR_BRAKE) mode = CBX_MODE_BRAKE;
  int32_t out = core->out[axis];

  if (gate == CBX_GATE_RUN) {
    const cbx_force_law* law = axis == CBX_AXIS_INSERTION ? &core->command.insertion : &core->command.rotation;
    const int32_t pos = cbx_axis_scale_position(s, e->count);
    const int32_t vel = cbx_axis_scale_position(s, e->vel_cps);
    const int32_t target = cbx_render_target(s, mode, cbx_force_law_eval(law, pos, vel), vel);
    out = cbx_render_slew(out, target, ceil_step(s->slew_per_ms, dt));
    /* A brake lets go at once when the motion turns (the slew limits only what it applies). */
    if (mode == CBX_MODE_BRAKE) out = cbx_render_target(s, mode, out, vel);
  } else if (gate == CBX_GATE_RAMP) {
    if (core->gate != CBX_GATE_RAMP) {
      /* Entering the ramp: fast enough to reach zero within CBX_RAMP_DOWN_MS. */
      const int32_t magnitude = out < 0 ? -out : out;
      const int32_t needed = magnitude / (int32_t)(CBX_RAMP_DOWN_MS - 1u) + 1;
      core->ramp_per_ms[axis] = needed > s->slew_per_ms ? needed : s->slew_per_ms;
    }
    const int32_t vel = cbx_axis_scale_position(s, e->vel_cps);
    out = cbx_render_target(s, mode, cbx_render_slew(out, 0, ceil_step(core->ramp_per_ms[axis], dt)), vel);
  } else {
    out = 0;
  }
  /* Limits lowered while rendering take effect at once, not at the slew rate. */
  if (out > s->max_out) out = s->max_out;
  if (out < -s->max_out) out = -s->max_out;
  core->out[axis] = out;

  /* Current clamp: fold the drive back while the measured current is over the limit. */
  const uint16_t limit = axis == CBX_AXIS_INSERTION ? core->settings.limits.insertion_max_current_mA
                                                    : core->settings.limits.rotation_max_current_mA;
  const int32_t current = current_mA < 0 ? -(int32_t)current_mA : current_mA;
  uint16_t cap = core->current_cap[axis];
  if (current > (int32_t)limit) {
    /* Over the limit: a quarter below the drive that caused it, tick after tick. */
    const int16_t last = core->drive[axis];
    const uint16_t applied = (uint16_t)(last < 0 ? -last : last);
    if (applied < cap) cap = applied;
    cap = (uint16_t)(cap - cap / 4u - (cap > 0u ? 1u : 0u));
  } else if (cap < CBX_PERMILLE_MAX) {
    cap++; /* recover at 1 per mille per tick */
  }
  core->current_cap[axis] = cap;

  /* The drive is a magnitude only for a brake; a motor renders even brake mode with the
   * force's sign (the sign is what makes it resist). */
  const uint8_t drive_mode = (mode == CBX_MODE_BRAKE && actuator == CBX_ACTUATOR_MOTOR) ? CBX_MODE_MOTOR : mode;
  int16_t drive = actuator == CBX_ACTUATOR_NONE ? 0 : cbx_render_drive(s, drive_mode, out);
  if (drive > (int16_t)cap) drive = (int16_t)cap;
  if (drive < -(int16_t)cap) drive = (int16_t)-(int16_t)cap;
  core->drive[axis] = drive;
}

static void publish_snapshot(cbx_core* core, uint32_t now, uint32_t dt, cbx_gate gate,
                             const cbx_safety_inputs* in) {
  cbx_state_report* r = &core->snapshot;
  r->header.version = CBX_PROTOCOL_VERSION;
  r->header.time_us = now;
  r->insertion_count = core->encoder[CBX_AXIS_INSERTION].count;
  r->rotation_count = core->encoder[CBX_AXIS_ROTATION].count;
  r->insertion_vel_cps = core->encoder[CBX_AXIS_INSERTION].vel_cps;
  r->rotation_vel_cps = core->encoder[CBX_AXIS_ROTATION].vel_cps;
  r->insertion_force_mN = core->out[CBX_AXIS_INSERTION];
  r->rotation_torque_uNm = core->out[CBX_AXIS_ROTATION];
  r->insertion_current_mA = in->current_mA[CBX_AXIS_INSERTION];
  r->rotation_current_mA = in->current_mA[CBX_AXIS_ROTATION];
  uint16_t status = 0u;
  if (gate == CBX_GATE_RUN) status |= CBX_STATUS_OUTPUT_ENABLED;
  if (in->calibrated) status |= CBX_STATUS_CALIBRATED;
  if (in->estop_pressed) status |= CBX_STATUS_ESTOP_PRESSED;
  if (core->safety.fresh) status |= CBX_STATUS_COMMAND_FRESH;
  if (core->selftest.state == CBX_SELFTEST_RUNNING) status |= CBX_STATUS_SELFTEST_RUNNING;
  r->status = status;
  r->faults = cbx_safety_faults(&core->safety, in->calibrated);
  r->command_seq_echo = core->command_seq_echo;
  r->encoder_errors = core->encoder_errors_seen > 0xFFFFu ? 0xFFFFu : (uint16_t)core->encoder_errors_seen;
  r->rx_errors = core->rx_errors > 0xFFFFu ? 0xFFFFu : (uint16_t)core->rx_errors;
  r->board_faults = core->config.board_faults;
  uint8_t mode = core->safety.mode;
  if (mode == CBX_MODE_MOTOR && core->config.axis[CBX_AXIS_INSERTION].actuator == CBX_ACTUATOR_BRAKE &&
      core->config.axis[CBX_AXIS_ROTATION].actuator == CBX_ACTUATOR_BRAKE)
    mode = CBX_MODE_BRAKE; /* what brakes can render */
  r->mode = (gate == CBX_GATE_RUN || gate == CBX_GATE_RAMP) ? mode : CBX_MODE_OFF;
  core->ms_accum_us += dt;
  while (core->ms_accum_us >= 1000u) {
    core->ms_accum_us -= 1000u;
    core->snapshot_ms++;
  }
}

void cbx_core_control_tick(cbx_core* core) {
  const uint32_t now = cbx_hal_time_us();
  const uint32_t dt = now - core->last_tick_us;
  core->last_tick_us = now;
  cbx_hal_watchdog_kick();

  cbx_safety_inputs in;
  in.now_us = now;
  in.estop_pressed = cbx_hal_estop_pressed();
  for (int i = 0; i < CBX_AXIS_COUNT; ++i) {
    cbx_encoder* e = &core->encoder[i];
    const uint32_t raw = e->source == CBX_ENCODER_COUNTER ? cbx_hal_encoder_counter((cbx_axis)i) : 0u;
    cbx_encoder_update(e, raw, now);
    in.current_mA[i] = cbx_hal_current_mA((cbx_axis)i);
  }
  apply_mailboxes(core, now, &in);
  /* Summed after the mailboxes, so that a counter reset is not taken for a new error. */
  const uint32_t errors = core->encoder[CBX_AXIS_INSERTION].errors + core->encoder[CBX_AXIS_ROTATION].errors;
  in.encoder_error = errors != core->encoder_errors_seen;
  core->encoder_errors_seen = errors;
  in.calibrated = core->scale[CBX_AXIS_INSERTION].valid && core->scale[CBX_AXIS_ROTATION].valid;

  cbx_gate gate = cbx_safety_update(&core->safety, &in, &core->settings.limits);
  if (core->bootloader_pending) gate = CBX_GATE_CUT;

  const bool hard_cut = gate == CBX_GATE_CUT && (in.estop_pressed || core->bootloader_pending ||
                                                 (core->safety.faults & CBX_FAULT_OVERCURRENT));
  bool rendered_by_selftest = false;
  if (core->selftest.state == CBX_SELFTEST_RUNNING) {
    if (hard_cut)
      cbx_selftest_abort(core, in.estop_pressed ? CBX_CHECK_ESTOP
                                                : CBX_CHECK_INSERTION_ACTUATOR | CBX_CHECK_ROTATION_ACTUATOR);
    else
      rendered_by_selftest = cbx_selftest_tick(core, now, in.estop_pressed, in.current_mA);
  }
  if (rendered_by_selftest) {
    gate = CBX_GATE_OFF;
  } else {
    for (int i = 0; i < CBX_AXIS_COUNT; ++i) render_axis(core, (cbx_axis)i, gate, dt, in.current_mA[i]);
  }
  core->gate = (uint8_t)gate;
  for (int i = 0; i < CBX_AXIS_COUNT; ++i) cbx_hal_actuator_set((cbx_axis)i, core->drive[i]);

  core->snapshot_seq++;
  publish_snapshot(core, now, dt, gate, &in);
  core->snapshot_seq++;
}

void cbx_core_state(cbx_core* core, cbx_state_report* out) {
  CBX_TICK_CONSISTENT(core, *out = core->snapshot);
}

void cbx_core_background(cbx_core* core) {
  uint8_t gate = core->gate;
  /* Saving stops the tick for 1-2 s (flash erase): only while nothing drives the actuators
   * (the self-test drives them with the gate off). */
  const bool driving = gate == CBX_GATE_RUN || gate == CBX_GATE_RAMP ||
                       core->selftest.state == CBX_SELFTEST_RUNNING;
  if (core->save_pending && !driving) {
    core->save_pending = 0u;
    cbx_settings s;
    uint32_t generation;
    do {
      generation = core->settings_generation;
      CBX_COMPILER_BARRIER();
      s = core->settings_slot[core->settings_published];
      CBX_COMPILER_BARRIER();
    } while (generation != core->settings_generation);
    uint8_t block[STORE_SIZE];
    s.calibration.header.version = CBX_PROTOCOL_VERSION;
    s.limits.header.version = CBX_PROTOCOL_VERSION;
    if (cbx_calibration_encode(&s.calibration, block) == CBX_OK &&
        cbx_limits_encode(&s.limits, block + CBX_REPORT_SIZE) == CBX_OK)
      (void)cbx_hal_store_save(block, sizeof block);
  }
  const uint32_t t = cbx_hal_time_us();
  bool on;
  if (core->snapshot.faults & ~CBX_FAULT_NOT_CALIBRATED) on = (t >> 17) & 1u;   /* ~4 Hz: fault */
  else if (gate == CBX_GATE_RUN) on = true;                                     /* rendering */
  else on = (t >> 19) & 1u;                                                      /* ~1 Hz: idle */
  cbx_hal_led_set(on);
}

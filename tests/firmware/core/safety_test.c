/* Every transition of the safety supervisor, with its timing, in virtual time through the
 * whole core (fake HAL): not calibrated, run, watchdog ramp and latch, acknowledge, E-stop,
 * over-current, encoder and bad-command faults, clamps and brake passivity. */
#include <string.h>

#include "cbx_test.h"
#include "fake_hal.h"

static cbx_core core;

static void setup(cbx_encoder_source source, cbx_actuator actuator, bool calibrate) {
  cbx_fake_reset();
  const cbx_core_config config = cbx_fake_config(source, actuator);
  cbx_core_init(&core, &config);
  if (calibrate) cbx_fake_calibrate(&core);
  cbx_fake_tick(&core);
}

/* Sets the default limits but for the watchdog timeout and the force limit. */
static void set_limits(uint16_t watchdog_ms, uint32_t max_force_mN) {
  cbx_settings defaults;
  cbx_core_default_settings(&defaults);
  cbx_limits l = defaults.limits;
  l.watchdog_timeout_ms = watchdog_ms;
  l.max_force_mN = max_force_mN;
  uint8_t bytes[CBX_REPORT_SIZE];
  CBX_CHECK_EQ(cbx_limits_encode(&l, bytes), CBX_OK);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, bytes, sizeof bytes), CBX_OK);
}

/* Sends the command every millisecond for `ms` milliseconds. */
static void stream(uint32_t ms, uint8_t mode, uint8_t flags, int32_t force_mN, int32_t torque_uNm) {
  const cbx_force_law f = cbx_fake_constant_law(force_mN, 40000);
  const cbx_force_law t = cbx_fake_constant_law(torque_uNm, 900000);
  for (uint32_t i = 0; i < ms; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, mode, flags, &f, &t), CBX_OK);
    cbx_fake_run_us(&core, 1000u);
  }
}

static void not_calibrated_blocks_output(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, false);
  stream(20, CBX_MODE_MOTOR, 0, 1500, 0);
  cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  CBX_CHECK_EQ(s.insertion_force_mN, 0);
  CBX_CHECK(s.faults & CBX_FAULT_NOT_CALIBRATED);
  CBX_CHECK(!(s.status & CBX_STATUS_OUTPUT_ENABLED));
  CBX_CHECK(!(s.status & CBX_STATUS_CALIBRATED));
  CBX_CHECK(s.status & CBX_STATUS_COMMAND_FRESH);
  /* Calibrating lifts the block (not latched). */
  cbx_fake_calibrate(&core);
  stream(20, CBX_MODE_MOTOR, 0, 1500, 0);
  s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.faults, 0);
  CBX_CHECK_EQ(s.insertion_force_mN, 1500);
}

static void motor_push_slews_to_target(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  const cbx_force_law f = cbx_fake_constant_law(1500, 5000);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &f, NULL), CBX_OK);
  cbx_fake_run_us(&core, 5000u); /* 100 mN/ms default slew */
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 500);
  CBX_CHECK(cbx_fake_state(&core).status & CBX_STATUS_OUTPUT_ENABLED);
  CBX_CHECK_EQ(cbx_fake_state(&core).mode, CBX_MODE_MOTOR);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &f, NULL), CBX_OK);
  cbx_fake_run_us(&core, 15000u);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 1500);
  CBX_CHECK_EQ(cbx_fake.drive[0], 188); /* 1500 / 8000 full scale, identity curve */
  /* Pull: negative drive for a motor. */
  stream(40, CBX_MODE_MOTOR, 0, -800, -10000);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, -800);
  CBX_CHECK_EQ(cbx_fake.drive[0], -100);
  CBX_CHECK_EQ(cbx_fake_state(&core).rotation_torque_uNm, -10000);
  CBX_CHECK_EQ(cbx_fake.drive[1], -500);
}

/* Runs ticks until the watchdog fault appears; returns the elapsed time since `since`. */
static uint32_t ticks_until_fault(uint16_t fault, uint32_t since, uint32_t max_us) {
  while (cbx_fake.time_us - since < max_us) {
    cbx_fake_tick(&core);
    if (cbx_fake_state(&core).faults & fault) break;
  }
  return cbx_fake.time_us - since;
}

static void watchdog_ramps_to_zero_and_latches(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(30, CBX_MODE_MOTOR, 0, 3000, 20000);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 3000);
  /* The last command was taken by the tick 0.9 ms ago (sent, then 1 ms of ticks); the fault
   * comes 50 ms after that. */
  const uint32_t last_command = cbx_fake.time_us - 900u;
  const uint32_t fault_after = ticks_until_fault(CBX_FAULT_WATCHDOG, last_command, 100000u);
  CBX_CHECK_EQ(fault_after, 50000);
  cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK(!(s.status & CBX_STATUS_COMMAND_FRESH));
  CBX_CHECK(!(s.status & CBX_STATUS_OUTPUT_ENABLED));
  CBX_CHECK(s.insertion_force_mN > 0); /* ramping, not cut */
  /* Ramp: monotone, zero within 20 ms. */
  const uint32_t fault_time = cbx_fake.time_us;
  int32_t previous = s.insertion_force_mN;
  while (cbx_fake_state(&core).insertion_force_mN != 0 || cbx_fake_state(&core).rotation_torque_uNm != 0) {
    cbx_fake_tick(&core);
    CBX_CHECK(cbx_fake_state(&core).insertion_force_mN <= previous);
    previous = cbx_fake_state(&core).insertion_force_mN;
    if (cbx_fake.time_us - fault_time > 30000u) break;
  }
  CBX_CHECK_RANGE(cbx_fake.time_us - fault_time, 10000, 20000);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  CBX_CHECK_EQ(cbx_fake.drive[1], 0);
  /* Latched: commands alone do not restart the output. */
  stream(20, CBX_MODE_MOTOR, 0, 3000, 0);
  s = cbx_fake_state(&core);
  CBX_CHECK(s.faults & CBX_FAULT_WATCHDOG);
  CBX_CHECK(s.status & CBX_STATUS_COMMAND_FRESH);
  CBX_CHECK_EQ(s.insertion_force_mN, 0);
  /* Acknowledged: cleared, the output slews back up. */
  stream(1, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 3000, 0);
  s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.faults, 0);
  CBX_CHECK_EQ(s.insertion_force_mN, 100);
  CBX_CHECK(s.status & CBX_STATUS_OUTPUT_ENABLED);
}

static void watchdog_timeout_follows_limits(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  set_limits(10u, 5000u);
  stream(5, CBX_MODE_MOTOR, 0, 500, 0);
  const uint32_t last_command = cbx_fake.time_us - 900u;
  CBX_CHECK_EQ(ticks_until_fault(CBX_FAULT_WATCHDOG, last_command, 100000u), 10000);
}

static void mode_off_stands_the_watchdog_down(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(10, CBX_MODE_MOTOR, 0, 500, 0);
  stream(1, CBX_MODE_OFF, 0, 0, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0); /* off: zero at once */
  cbx_fake_run_us(&core, 200000u);
  const cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.faults, 0);
  CBX_CHECK(!(s.status & CBX_STATUS_COMMAND_FRESH));
  CBX_CHECK_EQ(s.mode, CBX_MODE_OFF);
}

static void estop_cuts_at_once_and_latches(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(30, CBX_MODE_MOTOR, 0, 2000, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 250);
  cbx_fake.estop = true;
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.insertion_force_mN, 0);
  CBX_CHECK(s.faults & CBX_FAULT_ESTOP);
  CBX_CHECK(s.status & CBX_STATUS_ESTOP_PRESSED);
  /* ACK while still pressed: stays. */
  stream(5, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 2000, 0);
  CBX_CHECK(cbx_fake_state(&core).faults & CBX_FAULT_ESTOP);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  /* Released: still latched until acknowledged. */
  cbx_fake.estop = false;
  stream(5, CBX_MODE_MOTOR, 0, 2000, 0);
  s = cbx_fake_state(&core);
  CBX_CHECK(s.faults & CBX_FAULT_ESTOP);
  CBX_CHECK(!(s.status & CBX_STATUS_ESTOP_PRESSED));
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  stream(30, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 2000, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).faults, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 250);
}

static void overcurrent_folds_back_then_faults(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(50, CBX_MODE_MOTOR, 0, 4000, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 500);
  /* 0.5 ms over the 1500 mA limit: the drive folds back, no fault. */
  cbx_fake.current_mA[0] = 1600;
  cbx_fake_run_us(&core, 500u);
  CBX_CHECK(cbx_fake.drive[0] < 500);
  CBX_CHECK(cbx_fake.drive[0] > 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).faults, 0);
  cbx_fake.current_mA[0] = 1000;
  stream(120, CBX_MODE_MOTOR, 0, 4000, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 4000);
  CBX_CHECK_EQ(cbx_fake_state(&core).faults, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 500); /* recovered */
  /* 1 ms over: latched fault, cut in that tick. */
  cbx_fake.current_mA[0] = -1600;
  uint32_t start = cbx_fake.time_us;
  while (!(cbx_fake_state(&core).faults & CBX_FAULT_OVERCURRENT) && cbx_fake.time_us - start < 5000u)
    cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake.time_us - start, 1100); /* first sample at +100 us, 1 ms later: fault */
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 0);
  stream(2, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 4000, 0);
  CBX_CHECK(cbx_fake_state(&core).faults & CBX_FAULT_OVERCURRENT);
  cbx_fake.current_mA[0] = 0;
  stream(2, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 4000, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).faults, 0);
}

static void encoder_rest_is_not_a_move_or_a_fault(void) {
  setup(CBX_ENCODER_EDGES, CBX_ACTUATOR_MOTOR, true);
  cbx_core_encoder_rest(&core, CBX_AXIS_INSERTION, 3u); /* lines resting at 11 */
  cbx_core_encoder_edge(&core, CBX_AXIS_INSERTION, 3u); /* unchanged: nothing */
  cbx_core_encoder_edge(&core, CBX_AXIS_INSERTION, 1u); /* 11 -> 01: one count back */
  stream(2, CBX_MODE_MOTOR, 0, 0, 0);
  const cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.insertion_count, -1);
  CBX_CHECK_EQ(s.encoder_errors, 0);
  CBX_CHECK((s.faults & CBX_FAULT_ENCODER) == 0);
}

static void encoder_fault_ramps_down(void) {
  setup(CBX_ENCODER_EDGES, CBX_ACTUATOR_MOTOR, true);
  stream(30, CBX_MODE_MOTOR, 0, 1000, 0);
  cbx_core_encoder_edge(&core, CBX_AXIS_INSERTION, 3u); /* 00 -> 11: illegal */
  stream(1, CBX_MODE_MOTOR, 0, 1000, 0);
  cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK(s.faults & CBX_FAULT_ENCODER);
  CBX_CHECK_EQ(s.encoder_errors, 1);
  CBX_CHECK(s.insertion_force_mN < 1000);
  stream(20, CBX_MODE_MOTOR, 0, 1000, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 0);
  stream(20, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 1000, 0);
  s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.faults, 0);
  CBX_CHECK_EQ(s.insertion_force_mN, 1000);
  CBX_CHECK_EQ(s.encoder_errors, 1); /* the counter stays until reset */
}

static void bad_command_latches(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(30, CBX_MODE_MOTOR, 0, 1000, 0);
  const cbx_vector* v = cbx_fake_vector("command_motor_push");
  if (!v) return;
  uint8_t bytes[CBX_REPORT_SIZE];
  memcpy(bytes, v->bytes, sizeof bytes);
  bytes[20] ^= 0x01u; /* corrupt: CRC fails */
  CBX_CHECK_EQ(cbx_core_usb_out_report(&core, bytes, sizeof bytes), CBX_ERR_CRC);
  cbx_fake_run_us(&core, 20000u);
  cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK(s.faults & CBX_FAULT_BAD_COMMAND);
  CBX_CHECK_EQ(s.rx_errors, 1);
  CBX_CHECK_EQ(s.insertion_force_mN, 0);
  stream(20, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 1000, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).faults, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 1000);
}

static void clamps_whatever_the_command(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(600, CBX_MODE_MOTOR, 0, 40000, 900000);
  cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.insertion_force_mN, 5000);   /* default max_force */
  CBX_CHECK_EQ(s.rotation_torque_uNm, 50000); /* default max_torque */
  CBX_CHECK_EQ(cbx_fake.drive[1], 1000);      /* beyond the 20000 uNm full scale */
  set_limits(50u, 1200u);
  cbx_fake_tick(&core); /* a lowered limit applies at once, not at the slew rate */
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 1200);
  stream(100, CBX_MODE_MOTOR, 0, 40000, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 1200);
}

static void brake_only_resists_motion(void) {
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_BRAKE, true);
  /* The tool moves inwards at 10 counts per tick. */
  for (uint32_t i = 0; i < 50; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, NULL, NULL), CBX_OK);
    for (int k = 0; k < 10; ++k) {
      cbx_fake.counter[0] += 10u;
      cbx_fake_tick(&core);
    }
  }
  const cbx_force_law push = cbx_fake_constant_law(1000, 5000);
  const cbx_force_law resist = cbx_fake_constant_law(-1000, 5000);
  for (uint32_t i = 0; i < 20; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &push, NULL), CBX_OK);
    for (int k = 0; k < 10; ++k) {
      cbx_fake.counter[0] += 10u;
      cbx_fake_tick(&core);
      CBX_CHECK_EQ(cbx_fake.drive[0], 0);
    }
  }
  CBX_CHECK_EQ(cbx_fake_state(&core).mode, CBX_MODE_BRAKE); /* motor commanded, rendered as a brake */
  for (uint32_t i = 0; i < 20; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_BRAKE, 0, &resist, NULL), CBX_OK);
    for (int k = 0; k < 10; ++k) {
      cbx_fake.counter[0] += 10u;
      cbx_fake_tick(&core);
      CBX_CHECK(cbx_fake.drive[0] >= 0);
    }
  }
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, -1000);
  CBX_CHECK_EQ(cbx_fake.drive[0], 125); /* magnitude */
}

static void wall_renders_spring_and_damper(void) {
  /* calibration_identity: 38197 counts per metre, 8000 mN full scale. A 400 N/m wall at 10 mm
   * with 2 N*s/m damping, pushing back out (negative) when the tool is in the wall. */
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  const cbx_force_law wall = {.offset = 0, .pos0 = 10000, .stiffness = 400000, .damping = 2000,
                              .out_min = -5000, .out_max = 0};
  const int32_t count_um = 1000000 / 38197; /* ~26 um: the position resolution */
  cbx_fake.counter[0] = 573u; /* 15.0 mm: 5 mm into the wall */
  for (int i = 0; i < 300; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &wall, NULL), CBX_OK);
    cbx_fake_run_us(&core, 1000u);
  }
  cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_NEAR(s.insertion_force_mN, -2000, 400 * count_um / 1000 + 1); /* -400 N/m * 5 mm */
  CBX_CHECK_NEAR(cbx_fake.drive[0], -250, 2);
  /* Moving further in at 2000 counts/s (52.4 mm/s): the damper adds 2 N*s/m * 52.4 mm/s. */
  for (int i = 0; i < 50; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &wall, NULL), CBX_OK);
    for (int k = 0; k < 10; ++k) {
      if (k % 5 == 0) cbx_fake.counter[0] += 1u;
      cbx_fake_tick(&core);
    }
  }
  s = cbx_fake_state(&core);
  CBX_CHECK_NEAR(s.insertion_vel_cps, 2000, 20);
  const int32_t depth_um = (int32_t)((int64_t)cbx_fake.counter[0] * 1000000 / 38197) - 10000;
  CBX_CHECK_NEAR(s.insertion_force_mN, -(400 * depth_um / 1000) - 105, 12);
  /* Out of the wall: out_max 0, nothing rendered. */
  cbx_fake.counter[0] = 200u;
  for (int i = 0; i < 300; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &wall, NULL), CBX_OK);
    cbx_fake_run_us(&core, 1000u);
  }
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
}

/* The motor's drive never has the sign of the (estimated) insertion velocity. */
static void check_drive_resists_motion(void) {
  const int32_t vel = cbx_fake_state(&core).insertion_vel_cps;
  if (vel > 0) CBX_CHECK(cbx_fake.drive[0] <= 0);
  if (vel < 0) CBX_CHECK(cbx_fake.drive[0] >= 0);
}

/* Streams `law` on the insertion axis for `ms` milliseconds while the tool moves by
 * `counts_per_tick`; `check` (if any) runs after every tick. */
static void move(uint32_t ms, uint8_t mode, const cbx_force_law* law, int32_t counts_per_tick,
                 void (*check)(void)) {
  for (uint32_t i = 0; i < ms; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, mode, 0, law, NULL), CBX_OK);
    for (int k = 0; k < 10; ++k) {
      cbx_fake.counter[0] += (uint32_t)counts_per_tick;
      cbx_fake_tick(&core);
      if (check) check();
    }
  }
}

static void brake_mode_on_motors_resists(void) {
  /* A box with DC motors given a brake-mode command: the motor renders the resisting force
   * with its sign (a drive magnitude would push along the motion). */
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  const cbx_force_law resist_in = cbx_fake_constant_law(-1000, 5000);
  const cbx_force_law resist_out = cbx_fake_constant_law(1000, 5000);
  move(30, CBX_MODE_BRAKE, &resist_in, 10, check_drive_resists_motion); /* moving in */
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, -1000);
  CBX_CHECK_EQ(cbx_fake_state(&core).mode, CBX_MODE_BRAKE);
  CBX_CHECK_EQ(cbx_fake.drive[0], -125);
  move(30, CBX_MODE_BRAKE, &resist_out, -10, check_drive_resists_motion); /* moving out */
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 1000);
  CBX_CHECK_EQ(cbx_fake.drive[0], 125);
}

static bool released;
/* Once the velocity estimate says "moving out", a brake resisting insertion has let go. */
static void check_released_when_moving_out(void) {
  const cbx_state_report s = cbx_fake_state(&core);
  if (s.insertion_vel_cps >= 0) return;
  CBX_CHECK_EQ(s.insertion_force_mN, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  released = true;
}

static void brake_releases_at_once_when_the_motion_reverses(void) {
  /* Resisting insertion, then the tool is pulled back: the law's force (still negative) would
   * now push along the motion, so a brake lets go at once instead of slewing down. */
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_BRAKE, true);
  const cbx_force_law resist = cbx_fake_constant_law(-1000, 5000);
  move(30, CBX_MODE_BRAKE, &resist, 10, NULL);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, -1000);
  CBX_CHECK_EQ(cbx_fake.drive[0], 125);
  released = false;
  move(3, CBX_MODE_BRAKE, &resist, -10, check_released_when_moving_out); /* estimate turns in 2 ms */
  CBX_CHECK(released);
}

static void resetting_error_counters_is_not_an_encoder_fault(void) {
  setup(CBX_ENCODER_EDGES, CBX_ACTUATOR_MOTOR, true);
  cbx_core_encoder_edge(&core, CBX_AXIS_INSERTION, 3u); /* 00 -> 11: illegal */
  stream(2, CBX_MODE_MOTOR, 0, 1000, 0);
  CBX_CHECK(cbx_fake_state(&core).faults & CBX_FAULT_ENCODER);
  stream(20, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, 1000, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).faults, 0);
  CBX_CHECK_EQ(cbx_fake_state(&core).encoder_errors, 1);
  cbx_reset_counters r;
  memset(&r, 0, sizeof r);
  r.header.version = CBX_PROTOCOL_VERSION;
  r.mask = CBX_RESET_ERROR_COUNTERS;
  uint8_t bytes[CBX_REPORT_SIZE];
  CBX_CHECK_EQ(cbx_reset_counters_encode(&r, bytes), CBX_OK);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, bytes, sizeof bytes), CBX_OK);
  for (int k = 0; k < 3; ++k) {
    cbx_fake_tick(&core);
    const cbx_state_report s = cbx_fake_state(&core);
    CBX_CHECK_EQ(s.faults, 0);
    CBX_CHECK_EQ(s.encoder_errors, 0);
    CBX_CHECK(s.status & CBX_STATUS_OUTPUT_ENABLED);
  }
  /* A new illegal transition after the reset still latches. */
  cbx_core_encoder_edge(&core, CBX_AXIS_INSERTION, 0u);
  cbx_fake_tick(&core);
  CBX_CHECK(cbx_fake_state(&core).faults & CBX_FAULT_ENCODER);
  CBX_CHECK_EQ(cbx_fake_state(&core).encoder_errors, 1);
}

static void hard_cuts_interrupt_a_ramp_and_calibration_loss_cuts(void) {
  /* E-stop while the watchdog ramp is under way: zero in that tick, not at the ramp rate. */
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(30, CBX_MODE_MOTOR, 0, 3000, 0);
  CBX_CHECK(ticks_until_fault(CBX_FAULT_WATCHDOG, cbx_fake.time_us, 100000u) <= 51000u);
  cbx_fake_run_us(&core, 2000u);
  CBX_CHECK(cbx_fake_state(&core).insertion_force_mN > 1000); /* still ramping */
  cbx_fake.estop = true;
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  /* Calibration replaced by "none" while rendering: zero in the tick that takes it. */
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(30, CBX_MODE_MOTOR, 0, 2000, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 250);
  const cbx_vector* none = cbx_fake_vector("calibration_none");
  if (!none) return;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, none->bytes, none->length), CBX_OK);
  cbx_fake_tick(&core);
  const cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.insertion_force_mN, 0);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  CBX_CHECK(s.faults & CBX_FAULT_NOT_CALIBRATED);
  CBX_CHECK(!(s.status & CBX_STATUS_CALIBRATED));
}

static void acknowledge_is_not_lost_to_a_later_command(void) {
  /* Two commands between ticks (a queue drained at once): only the newer one is applied,
   * but an ACK_FAULTS in the older one still counts. */
  setup(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR, true);
  stream(10, CBX_MODE_MOTOR, 0, 1000, 0);
  cbx_fake.estop = true;
  cbx_fake_tick(&core);
  cbx_fake.estop = false;
  stream(5, CBX_MODE_MOTOR, 0, 1000, 0);
  CBX_CHECK(cbx_fake_state(&core).faults & CBX_FAULT_ESTOP);
  const cbx_force_law f = cbx_fake_constant_law(1000, 5000);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, &f, NULL), CBX_OK);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &f, NULL), CBX_OK);
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake_state(&core).faults, 0);
  /* Taken once: a later fault is not cleared by that old acknowledgement. */
  cbx_fake.estop = true;
  cbx_fake_tick(&core);
  cbx_fake.estop = false;
  stream(5, CBX_MODE_MOTOR, 0, 1000, 0);
  CBX_CHECK(cbx_fake_state(&core).faults & CBX_FAULT_ESTOP);
}

const cbx_test_case cbx_tests_safety[] = {
    {"not_calibrated_blocks_output", not_calibrated_blocks_output},
    {"motor_push_slews_to_target", motor_push_slews_to_target},
    {"watchdog_ramps_to_zero_and_latches", watchdog_ramps_to_zero_and_latches},
    {"watchdog_timeout_follows_limits", watchdog_timeout_follows_limits},
    {"mode_off_stands_the_watchdog_down", mode_off_stands_the_watchdog_down},
    {"estop_cuts_at_once_and_latches", estop_cuts_at_once_and_latches},
    {"overcurrent_folds_back_then_faults", overcurrent_folds_back_then_faults},
    {"encoder_rest_is_not_a_move_or_a_fault", encoder_rest_is_not_a_move_or_a_fault},
    {"encoder_fault_ramps_down", encoder_fault_ramps_down},
    {"bad_command_latches", bad_command_latches},
    {"clamps_whatever_the_command", clamps_whatever_the_command},
    {"brake_only_resists_motion", brake_only_resists_motion},
    {"wall_renders_spring_and_damper", wall_renders_spring_and_damper},
    {"brake_mode_on_motors_resists", brake_mode_on_motors_resists},
    {"brake_releases_at_once_when_the_motion_reverses", brake_releases_at_once_when_the_motion_reverses},
    {"resetting_error_counters_is_not_an_encoder_fault", resetting_error_counters_is_not_an_encoder_fault},
    {"hard_cuts_interrupt_a_ramp_and_calibration_loss_cuts", hard_cuts_interrupt_a_ramp_and_calibration_loss_cuts},
    {"acknowledge_is_not_lost_to_a_later_command", acknowledge_is_not_lost_to_a_later_command},
    {0, 0}};

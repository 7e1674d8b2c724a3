/* Protocol handling of the core against the golden vectors: the state report stream, commands,
 * every feature report, bad input, the bootloader request, self-test and settings storage. */
#include <string.h>

#include "cbx_test.h"
#include "fake_hal.h"

static cbx_core core;

static void setup(void) {
  cbx_fake_reset();
  const cbx_core_config config = cbx_fake_config(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR);
  cbx_core_init(&core, &config);
}

static void state_idle_matches_golden_vector(void) {
  setup();
  cbx_fake_calibrate(&core);
  uint8_t out[CBX_REPORT_SIZE];
  CBX_CHECK(!cbx_core_usb_in_report(&core, out)); /* nothing before the first millisecond */
  cbx_fake_run_us(&core, 1000u);
  CBX_CHECK(cbx_core_usb_in_report(&core, out));
  const cbx_vector* v = cbx_fake_vector("state_idle");
  if (!v) return;
  for (size_t i = 0; i < CBX_REPORT_SIZE; ++i) CBX_CHECK_EQ(out[i], v->bytes[i]);
}

static void state_report_every_millisecond(void) {
  setup();
  uint8_t out[CBX_REPORT_SIZE];
  unsigned reports = 0;
  uint16_t last_seq = 0;
  for (int tick = 0; tick < 1000; ++tick) {
    cbx_fake_tick(&core);
    if (cbx_core_usb_in_report(&core, out)) {
      cbx_state_report r;
      CBX_CHECK_EQ(cbx_state_decode(out, sizeof out, &r), CBX_OK);
      CBX_CHECK_EQ(r.header.seq, (uint16_t)(last_seq + 1u));
      CBX_CHECK_EQ(r.header.time_us % 1000u, 0);
      last_seq = r.header.seq;
      reports++;
    }
    CBX_CHECK(!cbx_core_usb_in_report(&core, out)); /* at most one per millisecond */
  }
  CBX_CHECK_EQ(reports, 100);
}

static void golden_commands_apply(void) {
  setup();
  cbx_fake_calibrate(&core);
  static const char* const names[] = {"command_brake_law", "command_motor_push", "command_off_ack"};
  static const uint8_t modes[] = {CBX_MODE_BRAKE, CBX_MODE_MOTOR, CBX_MODE_OFF};
  for (int i = 0; i < 3; ++i) {
    const cbx_vector* v = cbx_fake_vector(names[i]);
    if (!v) return;
    CBX_CHECK_EQ(cbx_core_usb_out_report(&core, v->bytes, v->length), CBX_OK);
    cbx_fake_run_us(&core, 1000u);
    const cbx_state_report s = cbx_fake_state(&core);
    CBX_CHECK_EQ(s.command_seq_echo, v->value.command.header.seq);
    CBX_CHECK_EQ(s.mode, modes[i]);
    CBX_CHECK_EQ(s.rx_errors, 0);
  }
  /* The motor push law (1500 mN offset) was rendered for 1 ms at 100 mN/ms. */
  const cbx_vector* push = cbx_fake_vector("command_motor_push");
  if (!push) return;
  CBX_CHECK_EQ(cbx_core_usb_out_report(&core, push->bytes, push->length), CBX_OK);
  cbx_fake_run_us(&core, 20000u);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_force_mN, 1500);
  CBX_CHECK_EQ(cbx_fake_state(&core).rotation_torque_uNm, -300);
}

static cbx_status send(const cbx_vector* v) {
  if (strcmp(v->kind, "command") == 0) return cbx_core_usb_out_report(&core, v->bytes, v->length);
  return cbx_core_usb_feature_set(&core, v->bytes, v->length);
}

static void bad_vectors_rejected_and_counted(void) {
  setup();
  unsigned rejected = 0;
  for (size_t i = 0; i < cbx_vector_count; ++i) {
    const cbx_vector* v = &cbx_vectors[i];
    if (v->expect == CBX_OK || strcmp(v->kind, "state") == 0 || strcmp(v->kind, "device_info") == 0)
      continue;
    const cbx_status st = send(v);
    if (st != v->expect) cbx_test_fail(__FILE__, __LINE__, "%s: got %d, expected %d", v->name, st, v->expect);
    rejected++;
  }
  CBX_CHECK(rejected >= 5u);
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake_state(&core).rx_errors, rejected);
  CBX_CHECK_EQ(cbx_fake.bootloader_requests, 0);
  /* A state report or device info sent to the box, a truncated report, NULL: rejected. */
  const cbx_vector* idle = cbx_fake_vector("state_idle");
  const cbx_vector* info = cbx_fake_vector("device_info");
  if (!idle || !info) return;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, idle->bytes, idle->length), CBX_ERR_REPORT_ID);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, info->bytes, info->length), CBX_ERR_REPORT_ID);
  CBX_CHECK_EQ(cbx_core_usb_out_report(&core, idle->bytes, idle->length), CBX_ERR_REPORT_ID);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, info->bytes, 10), CBX_ERR_LENGTH);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, NULL, 64), CBX_ERR_NULL);
  CBX_CHECK_EQ(cbx_core_usb_out_report(&core, NULL, 64), CBX_ERR_NULL);
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake_state(&core).rx_errors, rejected + 6u);
}

static void calibration_and_limits_round_trip(void) {
  setup();
  for (size_t i = 0; i < cbx_vector_count; ++i) {
    const cbx_vector* v = &cbx_vectors[i];
    if (v->expect != CBX_OK) continue;
    uint8_t out[CBX_REPORT_SIZE];
    if (strcmp(v->kind, "calibration") == 0) {
      CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
      CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_CALIBRATION, out), CBX_OK);
      cbx_calibration got;
      CBX_CHECK_EQ(cbx_calibration_decode(out, sizeof out, &got), CBX_OK);
      got.header = v->value.calibration.header; /* then it must re-encode to the vector */
      CBX_CHECK_EQ(cbx_calibration_encode(&got, out), CBX_OK);
      CBX_CHECK(memcmp(out, v->bytes, sizeof out) == 0);
    } else if (strcmp(v->kind, "limits") == 0) {
      CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
      CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_LIMITS, out), CBX_OK);
      cbx_limits got;
      CBX_CHECK_EQ(cbx_limits_decode(out, sizeof out, &got), CBX_OK);
      got.header = v->value.limits.header;
      CBX_CHECK_EQ(cbx_limits_encode(&got, out), CBX_OK);
      CBX_CHECK(memcmp(out, v->bytes, sizeof out) == 0);
    }
  }
  /* The defaults are the documented ones (limits_default). */
  setup();
  uint8_t out[CBX_REPORT_SIZE];
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_LIMITS, out), CBX_OK);
  const cbx_vector* d = cbx_fake_vector("limits_default");
  if (!d) return;
  for (size_t i = CBX_HEADER_SIZE; i < CBX_CRC_OFFSET; ++i) CBX_CHECK_EQ(out[i], d->bytes[i]);
}

static void device_info_describes_the_board(void) {
  setup();
  uint8_t out[CBX_REPORT_SIZE];
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_DEVICE_INFO, out), CBX_OK);
  cbx_device_info info;
  CBX_CHECK_EQ(cbx_device_info_decode(out, sizeof out, &info), CBX_OK);
  CBX_CHECK(strcmp(info.serial, "CBX-0001") == 0);
  CBX_CHECK(strcmp(info.board, "fake") == 0);
  CBX_CHECK_EQ(info.fw_major, CBX_FW_MAJOR);
  CBX_CHECK_EQ(info.protocol_minor, CBX_PROTOCOL_MINOR);
  CBX_CHECK(strcmp(info.build, "test") == 0);
  CBX_CHECK_EQ(info.insertion_actuator, CBX_ACTUATOR_MOTOR);
  CBX_CHECK_EQ(info.rotation_encoder_cpr, 2400);
  /* Set-only and unknown reports cannot be read. */
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_ENTER_BOOTLOADER, out), CBX_ERR_REPORT_ID);
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_RESET_COUNTERS, out), CBX_ERR_REPORT_ID);
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, 0x7Fu, out), CBX_ERR_REPORT_ID);
  /* The state can be read on the control endpoint too. */
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_STATE, out), CBX_OK);
}

/* The version and build are the running image's (the port reads them from its image info
 * block), not constants of the core. */
static void device_info_reports_the_image(void) {
  cbx_fake_reset();
  cbx_core_config config = cbx_fake_config(CBX_ENCODER_COUNTER, CBX_ACTUATOR_BRAKE);
  config.fw_version[0] = 1u;
  config.fw_version[1] = 7u;
  config.fw_version[2] = 3u;
  strcpy(config.build, "abc1234");
  cbx_core_init(&core, &config);
  uint8_t out[CBX_REPORT_SIZE];
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_DEVICE_INFO, out), CBX_OK);
  cbx_device_info info;
  CBX_CHECK_EQ(cbx_device_info_decode(out, sizeof out, &info), CBX_OK);
  CBX_CHECK_EQ(info.fw_minor, 7);
  CBX_CHECK_EQ(info.fw_patch, 3);
  CBX_CHECK(strcmp(info.build, "abc1234") == 0);
}

/* A board fault (the crystal did not start) is in every state report from the first one on,
 * is not cleared by ACK_FAULTS, and does not block the output. */
static void board_fault_is_reported_not_latched_not_blocking(void) {
  cbx_fake_reset();
  cbx_core_config config = cbx_fake_config(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR);
  config.board_faults = CBX_BOARD_FAULT_HSE;
  cbx_core_init(&core, &config);
  CBX_CHECK_EQ(cbx_fake_state(&core).board_faults, CBX_BOARD_FAULT_HSE);
  cbx_fake_calibrate(&core);
  const cbx_force_law push = cbx_fake_constant_law(1000, 5000);
  for (int ms = 0; ms < 20; ++ms) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, &push, NULL), CBX_OK);
    cbx_fake_run_us(&core, 1000u);
  }
  const cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK(s.status & CBX_STATUS_OUTPUT_ENABLED);
  CBX_CHECK_EQ(s.faults, 0);
  CBX_CHECK_EQ(s.board_faults, CBX_BOARD_FAULT_HSE);
  CBX_CHECK(cbx_fake.drive[CBX_AXIS_INSERTION] > 0);
}

/* The port could not send reports: counted in the next ones (IN and GET_REPORT), saturating. */
static void dropped_in_reports_are_counted(void) {
  setup();
  uint8_t out[CBX_REPORT_SIZE];
  cbx_state_report r;
  cbx_fake_run_us(&core, 1000u);
  CBX_CHECK(cbx_core_usb_in_report(&core, out));
  cbx_core_usb_in_dropped(&core);
  cbx_fake_run_us(&core, 1000u);
  CBX_CHECK(cbx_core_usb_in_report(&core, out));
  cbx_core_usb_in_dropped(&core);
  cbx_fake_run_us(&core, 1000u);
  CBX_CHECK(cbx_core_usb_in_report(&core, out));
  CBX_CHECK_EQ(cbx_state_decode(out, sizeof out, &r), CBX_OK);
  CBX_CHECK_EQ(r.in_dropped, 2);
  for (int i = 0; i < 70000; ++i) cbx_core_usb_in_dropped(&core);
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_STATE, out), CBX_OK);
  CBX_CHECK_EQ(cbx_state_decode(out, sizeof out, &r), CBX_OK);
  CBX_CHECK_EQ(r.in_dropped, 0xFFFF);
}

/* USB reset or suspend: zero in the next tick, no fault, the echo of the host's last command
 * kept; the next command renders again. */
static void usb_reset_stops_rendering_in_the_next_tick(void) {
  setup();
  cbx_fake_calibrate(&core);
  const cbx_force_law push = cbx_fake_constant_law(1500, 5000);
  for (int ms = 0; ms < 10; ++ms) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0u, &push, NULL), CBX_OK);
    cbx_fake_run_us(&core, 1000u);
  }
  CBX_CHECK(cbx_fake.drive[CBX_AXIS_INSERTION] > 0);
  const uint16_t echo = cbx_fake_state(&core).command_seq_echo;
  cbx_core_usb_reset(&core);
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake.drive[CBX_AXIS_INSERTION], 0);
  cbx_fake_run_us(&core, 100000u); /* twice the watchdog timeout */
  const cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.mode, CBX_MODE_OFF);
  CBX_CHECK_EQ(s.faults, 0);
  CBX_CHECK_EQ(s.command_seq_echo, echo);
  CBX_CHECK_EQ(cbx_fake.drive[CBX_AXIS_INSERTION], 0);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0u, &push, NULL), CBX_OK);
  cbx_fake_run_us(&core, 2000u);
  CBX_CHECK(cbx_fake.drive[CBX_AXIS_INSERTION] > 0);
}

static void reset_counters_zeroes_what_it_names(void) {
  setup();
  cbx_fake.counter[0] = 1234u;
  cbx_fake.counter[1] = 777u;
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_count, 1234);
  const cbx_vector* v = cbx_fake_vector("reset_counters_all");
  if (!v) return;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
  cbx_fake_tick(&core);
  const uint8_t mask = v->value.reset_counters.mask;
  const cbx_state_report s = cbx_fake_state(&core);
  CBX_CHECK_EQ(s.insertion_count, (mask & CBX_RESET_INSERTION_COUNT) ? 0 : 1234);
  CBX_CHECK_EQ(s.rotation_count, (mask & CBX_RESET_ROTATION_COUNT) ? 0 : 777);
  /* Counting continues from zero. */
  cbx_fake.counter[0] += 10u;
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake_state(&core).insertion_count, (mask & CBX_RESET_INSERTION_COUNT) ? 10 : 1244);
}

static void enter_bootloader_cuts_outputs(void) {
  setup();
  cbx_fake_calibrate(&core);
  const cbx_force_law f = cbx_fake_constant_law(2000, 5000);
  for (int i = 0; i < 30; ++i) {
    CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &f, NULL), CBX_OK);
    cbx_fake_run_us(&core, 1000u);
  }
  CBX_CHECK_EQ(cbx_fake.drive[0], 250);
  const cbx_vector* v = cbx_fake_vector("enter_bootloader");
  if (!v) return;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
  CBX_CHECK_EQ(cbx_fake.bootloader_requests, 1);
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
}

static void selftest_reports_its_checks(void) {
  setup();
  cbx_fake_calibrate(&core);
  cbx_fake.mA_per_permille = 2; /* 200 per mille -> 400 mA: healthy */
  const cbx_vector* v = cbx_fake_vector("selftest_start");
  if (!v) return;
  uint8_t out[CBX_REPORT_SIZE];
  cbx_selftest r;
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_SELFTEST, out), CBX_OK);
  CBX_CHECK_EQ(cbx_selftest_decode(out, sizeof out, &r), CBX_OK);
  CBX_CHECK_EQ(r.state, CBX_SELFTEST_NEVER_RUN);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
  cbx_fake_run_us(&core, 10000u);
  CBX_CHECK(cbx_fake_state(&core).status & CBX_STATUS_SELFTEST_RUNNING);
  CBX_CHECK_EQ(cbx_fake.drive[0], 200);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_ERR_STATE); /* busy */
  cbx_fake_run_us(&core, 40000u);
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_SELFTEST, out), CBX_OK);
  CBX_CHECK_EQ(cbx_selftest_decode(out, sizeof out, &r), CBX_OK);
  CBX_CHECK_EQ(r.state, CBX_SELFTEST_PASSED);
  CBX_CHECK_EQ(r.insertion_current_mA, 400);
  CBX_CHECK_EQ(r.rotation_current_mA, 400);
  CBX_CHECK_EQ(r.supply_mV, 12000);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  CBX_CHECK_EQ(cbx_fake.drive[1], 0);
  /* A dead rotation actuator (no current) fails its check. */
  cbx_fake.mA_per_permille = 0;
  cbx_fake.current_mA[0] = 300;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
  cbx_fake_run_us(&core, 50000u);
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_SELFTEST, out), CBX_OK);
  CBX_CHECK_EQ(cbx_selftest_decode(out, sizeof out, &r), CBX_OK);
  CBX_CHECK_EQ(r.state, CBX_SELFTEST_FAILED);
  CBX_CHECK_EQ(r.failed_checks, CBX_CHECK_ROTATION_ACTUATOR);
  /* E-stop during the test: aborted at once. */
  cbx_fake.mA_per_permille = 2;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
  cbx_fake_run_us(&core, 5000u);
  cbx_fake.estop = true;
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake.drive[0], 0);
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_SELFTEST, out), CBX_OK);
  CBX_CHECK_EQ(cbx_selftest_decode(out, sizeof out, &r), CBX_OK);
  CBX_CHECK_EQ(r.state, CBX_SELFTEST_FAILED);
  CBX_CHECK(r.failed_checks & CBX_CHECK_ESTOP);
  /* Not while rendering. */
  cbx_fake.estop = false;
  const cbx_force_law f = cbx_fake_constant_law(500, 5000);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, CBX_CMD_ACK_FAULTS, &f, NULL), CBX_OK);
  cbx_fake_run_us(&core, 1000u);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_ERR_STATE);
}

static void settings_persist_across_restart(void) {
  setup();
  cbx_core_background(&core);
  CBX_CHECK_EQ(cbx_fake.saves, 0);
  const cbx_vector* v = cbx_fake_vector("calibration_brake");
  if (!v) return;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, v->bytes, v->length), CBX_OK);
  cbx_fake_tick(&core);
  cbx_core_background(&core);
  CBX_CHECK_EQ(cbx_fake.saves, 1);
  cbx_core_background(&core);
  CBX_CHECK_EQ(cbx_fake.saves, 1); /* once per change */
  /* Restart: loaded from the store. */
  const cbx_core_config config = cbx_fake_config(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR);
  cbx_core_init(&core, &config);
  cbx_fake_tick(&core);
  CBX_CHECK(cbx_fake_state(&core).status & CBX_STATUS_CALIBRATED);
  uint8_t out[CBX_REPORT_SIZE];
  cbx_calibration got;
  CBX_CHECK_EQ(cbx_core_usb_feature_get(&core, CBX_ID_CALIBRATION, out), CBX_OK);
  CBX_CHECK_EQ(cbx_calibration_decode(out, sizeof out, &got), CBX_OK);
  CBX_CHECK_EQ(got.insertion_counts_per_m, v->value.calibration.insertion_counts_per_m);
  /* A corrupted store is ignored: defaults, not calibrated. */
  cbx_fake.store[20] ^= 0xFFu;
  cbx_core_init(&core, &config);
  cbx_fake_tick(&core);
  CBX_CHECK(!(cbx_fake_state(&core).status & CBX_STATUS_CALIBRATED));
}

static void settings_wait_while_outputs_are_driven(void) {
  /* Saving erases a flash sector with the tick stopped for 1-2 s: never while rendering and
   * never while the self-test drives an actuator; afterwards it happens. */
  setup();
  cbx_fake_calibrate(&core);
  cbx_fake_tick(&core);
  cbx_core_background(&core);
  CBX_CHECK_EQ(cbx_fake.saves, 1);
  const cbx_vector* limits = cbx_fake_vector("limits_default");
  const cbx_vector* start = cbx_fake_vector("selftest_start");
  if (!limits || !start) return;
  cbx_fake.mA_per_permille = 2;
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, start->bytes, start->length), CBX_OK);
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_fake.drive[0], 200);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, limits->bytes, limits->length), CBX_OK);
  for (int i = 0; i < 500; ++i) { /* the test takes 40 ms */
    cbx_fake_tick(&core);
    cbx_core_background(&core);
    if (cbx_fake.drive[0] != 0 || cbx_fake.drive[1] != 0) CBX_CHECK_EQ(cbx_fake.saves, 1);
  }
  CBX_CHECK_EQ(cbx_fake.saves, 2);
  /* Rendering: deferred until the output is off again. */
  const cbx_force_law f = cbx_fake_constant_law(500, 5000);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &f, NULL), CBX_OK);
  cbx_fake_tick(&core);
  CBX_CHECK_EQ(cbx_core_usb_feature_set(&core, limits->bytes, limits->length), CBX_OK);
  cbx_fake_tick(&core);
  cbx_core_background(&core);
  CBX_CHECK_EQ(cbx_fake.saves, 2);
  CBX_CHECK_EQ(cbx_fake_command(&core, CBX_MODE_OFF, 0, NULL, NULL), CBX_OK);
  cbx_fake_tick(&core);
  cbx_core_background(&core);
  CBX_CHECK_EQ(cbx_fake.saves, 3);
}

const cbx_test_case cbx_tests_protocol[] = {
    {"state_idle_matches_golden_vector", state_idle_matches_golden_vector},
    {"state_report_every_millisecond", state_report_every_millisecond},
    {"golden_commands_apply", golden_commands_apply},
    {"bad_vectors_rejected_and_counted", bad_vectors_rejected_and_counted},
    {"calibration_and_limits_round_trip", calibration_and_limits_round_trip},
    {"device_info_describes_the_board", device_info_describes_the_board},
    {"device_info_reports_the_image", device_info_reports_the_image},
    {"board_fault_is_reported_not_latched_not_blocking", board_fault_is_reported_not_latched_not_blocking},
    {"dropped_in_reports_are_counted", dropped_in_reports_are_counted},
    {"usb_reset_stops_rendering_in_the_next_tick", usb_reset_stops_rendering_in_the_next_tick},
    {"reset_counters_zeroes_what_it_names", reset_counters_zeroes_what_it_names},
    {"enter_bootloader_cuts_outputs", enter_bootloader_cuts_outputs},
    {"selftest_reports_its_checks", selftest_reports_its_checks},
    {"settings_persist_across_restart", settings_persist_across_restart},
    {"settings_wait_while_outputs_are_driven", settings_wait_while_outputs_are_driven},
    {0, 0}};

#ifndef CBX_CORE_H
#define CBX_CORE_H
/* The portable firmware core: encoders, force rendering at the control rate, the safety
 * supervisor and protocol v1 handling. No allocation, no vendor headers; the board is reached
 * only through firmware/cbx_hal.h. One cbx_core instance per box, owned by the port.
 *
 * Contexts: cbx_core_control_tick() runs at CBX_CORE_TICK_HZ with the highest priority;
 * the cbx_core_usb_* entry points run in the USB context (lower priority, or the same thread);
 * cbx_core_background() runs in the main loop. cbx_core_encoder_edge() must not run
 * concurrently with the tick (same priority or same thread). The hand-over between contexts
 * relies on the tick never being preempted by them (interrupt priorities); a hosted program
 * with threads calls all entry points from one thread or under one lock. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "firmware/cbx_encoder.h"
#include "firmware/cbx_hal.h"
#include "firmware/cbx_render.h"
#include "firmware/cbx_safety.h"
#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_protocol.h"
#include "protocol/cbx_state_report.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CBX_CORE_TICK_HZ 10000u
#define CBX_CORE_TICK_US (1000000u / CBX_CORE_TICK_HZ)
#define CBX_FW_MAJOR 1u
#define CBX_FW_MINOR 0u
#define CBX_FW_PATCH 0u

/* What the port tells the core about the board. */
typedef struct {
  uint8_t encoder_source;  /* cbx_encoder_source */
  uint8_t counter_bits;    /* hardware counter width (counter source), e.g. 16 or 32 */
  uint8_t actuator;        /* cbx_actuator */
  uint32_t encoder_cpr;    /* encoder counts per encoder revolution (x4), for device info */
} cbx_axis_config;

typedef struct {
  char serial[CBX_TEXT_FIELD + 1]; /* ASCII 0x20..0x7E */
  char board[CBX_TEXT_FIELD + 1];  /* e.g. "stm32f411-bp", "cathbox-emu" */
  cbx_axis_config axis[CBX_AXIS_COUNT];
  uint8_t fw_version[3];           /* major, minor, patch of the running image (its info block) */
  char build[CBX_BUILD_FIELD + 1]; /* build identifier of the running image, ASCII */
  uint8_t board_faults;            /* CBX_BOARD_FAULT_* the port found at start-up (e.g. no HSE) */
} cbx_core_config;

/* Settings persisted through cbx_hal_store_*: calibration and limits. */
typedef struct {
  cbx_calibration calibration;
  cbx_limits limits;
} cbx_settings;

/* Self-test progress (run by the control tick). */
typedef struct {
  uint8_t state;        /* cbx_selftest_state */
  uint8_t phase;
  uint32_t phase_start_us;
  uint32_t errors_at_start[CBX_AXIS_COUNT];
  cbx_selftest result;
} cbx_selftest_run;

/* Everything below is private to the core; it is in the header only so that the port can
 * allocate the instance statically. */
typedef struct {
  cbx_core_config config;

  /* Mailboxes from the USB context to the tick: two slots each, the tick reads the published
   * one (the writer never preempts the tick). */
  cbx_command_report command_slot[2];
  volatile uint8_t command_published;
  volatile uint32_t command_generation;
  volatile uint8_t ack_pending;        /* an ACK_FAULTS arrived since the tick last took one */
  cbx_settings settings_slot[2];
  cbx_axis_scale scale_slot[2][CBX_AXIS_COUNT]; /* derived from settings_slot by the writer, so the tick has no divisions */
  volatile uint8_t settings_published;
  volatile uint32_t settings_generation;
  volatile uint8_t reset_mask;
  volatile uint32_t reset_generation;
  volatile uint32_t selftest_generation;
  volatile uint32_t bad_command_count; /* decode failures of OUT reports */
  volatile uint8_t bootloader_pending;
  volatile uint8_t save_pending;
  volatile uint32_t rx_errors;

  /* Owned by the tick. */
  uint32_t applied_command_generation, applied_settings_generation, applied_reset_generation,
      applied_selftest_generation, applied_bad_commands;
  cbx_command_report command;   /* the command in force */
  cbx_settings settings;        /* the settings in force */
  cbx_axis_scale scale[CBX_AXIS_COUNT];
  cbx_encoder encoder[CBX_AXIS_COUNT];
  cbx_safety safety;
  cbx_selftest_run selftest;
  int32_t out[CBX_AXIS_COUNT];          /* output after clamps and slew (mN, uNm) */
  int32_t ramp_per_ms[CBX_AXIS_COUNT];  /* ramp rate while the gate is RAMP */
  int16_t drive[CBX_AXIS_COUNT];
  uint16_t current_cap[CBX_AXIS_COUNT]; /* current foldback: drive cap, per mille */
  uint8_t gate;                         /* cbx_gate of the last tick */
  uint32_t last_tick_us;
  uint32_t encoder_errors_seen;
  uint16_t command_seq_echo;
  uint8_t ticked;

  /* Snapshot for the IN report, written by the tick, read by the USB context. */
  volatile uint32_t snapshot_seq;
  cbx_state_report snapshot;
  volatile uint32_t snapshot_ms;        /* milliseconds counted by the tick */
  uint32_t ms_accum_us;
  uint32_t reported_ms;                 /* USB context: ms of the last IN report */
  uint16_t in_seq, feature_seq;
  uint32_t in_dropped;                  /* USB context: IN reports the port could not send */
} cbx_core;

/* Defaults for a board (not calibrated, default limits). */
void cbx_core_default_settings(cbx_settings* settings);

/* Initialises the core; loads persisted settings through cbx_hal_store_load(). Outputs off. */
void cbx_core_init(cbx_core* core, const cbx_core_config* config);
/* The control tick (CBX_CORE_TICK_HZ): sensors, safety, force rendering, actuator drive. */
void cbx_core_control_tick(cbx_core* core);
/* One A/B sample of an edge-source encoder: bit 0 = A, bit 1 = B. Decoding starts from
 * A/B = 00 at cbx_core_init(); a source whose lines rest elsewhere then reads as a move (or
 * an illegal transition) on its first sample, unless cbx_core_encoder_rest() gave it first. */
void cbx_core_encoder_edge(cbx_core* core, cbx_axis axis, uint8_t ab);
/* The present A/B state of an edge-source encoder's lines, taken without counting (after
 * cbx_core_init(), for lines that do not rest at 00). */
void cbx_core_encoder_rest(cbx_core* core, cbx_axis axis, uint8_t ab);
/* Main loop work: persists changed settings while outputs are off, drives the LED. */
void cbx_core_background(cbx_core* core);

/* An interrupt OUT report (command) arrived. Returns the decode status; failures count as
 * rx errors and latch CBX_FAULT_BAD_COMMAND. */
cbx_status cbx_core_usb_out_report(cbx_core* core, const uint8_t* data, size_t length);
/* Fills the next state report for interrupt IN; false when no new millisecond has passed
 * since the last one. Call once per USB frame. */
bool cbx_core_usb_in_report(cbx_core* core, uint8_t out[CBX_REPORT_SIZE]);
/* GET_REPORT for a feature (or the state) report `id`; CBX_ERR_REPORT_ID when that report
 * cannot be read (the port then stalls). */
cbx_status cbx_core_usb_feature_get(cbx_core* core, uint8_t id, uint8_t out[CBX_REPORT_SIZE]);
/* SET_REPORT of a feature report; any failure is counted as an rx error (the port stalls). */
cbx_status cbx_core_usb_feature_set(cbx_core* core, const uint8_t* data, size_t length);

/* The port could not send the IN report cbx_core_usb_in_report() gave it (its endpoint FIFO
 * had no room): counted in the state reports' in_dropped. USB context. */
void cbx_core_usb_in_dropped(cbx_core* core);
/* The host is gone: USB bus reset, suspend or detach. Outputs go to zero in the next tick and
 * stay off (as after a command with mode off: no fault, the watchdog stands down) until the
 * host commands again. The port also cuts its outputs at once. USB context. */
void cbx_core_usb_reset(cbx_core* core);

/* A consistent copy of the latest state (what the next IN report carries, header aside). */
void cbx_core_state(cbx_core* core, cbx_state_report* out);

#ifdef __cplusplus
}
#endif
#endif

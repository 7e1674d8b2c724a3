#ifndef CBX_STATE_REPORT_H
#define CBX_STATE_REPORT_H
/* IN state report (box -> host, report ID 0x01, every 1 ms). Layout in protocol/README.md. */
#include "protocol/cbx_protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Status bits (what the box is doing now). */
enum {
  CBX_STATUS_OUTPUT_ENABLED = 1u << 0, /* actuators are driven */
  CBX_STATUS_CALIBRATED = 1u << 1,     /* calibration present and valid */
  CBX_STATUS_ESTOP_PRESSED = 1u << 2,  /* the E-stop loop is open right now */
  CBX_STATUS_COMMAND_FRESH = 1u << 3,  /* a valid command arrived within the watchdog timeout */
  CBX_STATUS_SELFTEST_RUNNING = 1u << 4,
  CBX_STATUS_ALL = 0x1Fu
};

/* Fault bits: latched until the host acknowledges them (command flag ACK_FAULTS), except
 * NOT_CALIBRATED, which follows the calibration. */
enum {
  CBX_FAULT_WATCHDOG = 1u << 0,        /* no valid command within the watchdog timeout */
  CBX_FAULT_ESTOP = 1u << 1,           /* the E-stop was pressed */
  CBX_FAULT_ENCODER = 1u << 2,         /* illegal quadrature transitions seen */
  CBX_FAULT_OVERCURRENT = 1u << 3,     /* an actuator current exceeded its limit */
  CBX_FAULT_NOT_CALIBRATED = 1u << 4,  /* force output is blocked until calibrated */
  CBX_FAULT_BAD_COMMAND = 1u << 5,     /* a command failed to decode (length, version, CRC, range) */
  CBX_FAULT_ALL = 0x3Fu
};

/* Board faults (protocol minor 1): conditions of the board found by the firmware, reported as
 * long as they last, never latched, and not blocking the output. In their own byte, so that
 * protocol 1.0 hosts (which range-check `faults`) still decode the report. */
enum {
  CBX_BOARD_FAULT_HSE = 1u << 0, /* the crystal (HSE) did not start: running on the internal
                                    oscillator, USB timing out of spec */
  CBX_BOARD_FAULT_ALL = 0x01u
};

/* Actuation mode, shared by the command and state reports. */
typedef enum {
  CBX_MODE_OFF = 0,   /* outputs disabled */
  CBX_MODE_BRAKE = 1, /* magnetic-particle brakes: can only resist motion */
  CBX_MODE_MOTOR = 2  /* DC motors: can resist and push */
} cbx_mode;

typedef struct {
  cbx_header header;
  int32_t insertion_count;      /* encoder counts, 32-bit extended */
  int32_t rotation_count;
  int32_t insertion_vel_cps;    /* velocity estimate, counts per second */
  int32_t rotation_vel_cps;
  int32_t insertion_force_mN;   /* actuator output readback (force being rendered) */
  int32_t rotation_torque_uNm;  /* actuator output readback (torque being rendered) */
  int16_t insertion_current_mA; /* measured actuator current */
  int16_t rotation_current_mA;
  uint16_t status;              /* CBX_STATUS_* */
  uint16_t faults;              /* CBX_FAULT_* */
  uint16_t command_seq_echo;    /* seq of the last valid command applied */
  uint16_t encoder_errors;      /* illegal transitions, both axes, saturating at 65535 */
  uint16_t rx_errors;           /* rejected OUT/feature reports, saturating at 65535 */
  uint8_t mode;                 /* cbx_mode in force */
  uint8_t board_faults;         /* CBX_BOARD_FAULT_* (protocol minor 1) */
  uint16_t in_dropped;          /* IN reports the box could not send (endpoint FIFO full),
                                   saturating at 65535 (protocol minor 1) */
} cbx_state_report;

cbx_status cbx_state_encode(const cbx_state_report* state, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_state_decode(const uint8_t* in, size_t length, cbx_state_report* state);

#ifdef __cplusplus
}
#endif
#endif

#ifndef CBX_SAFETY_H
#define CBX_SAFETY_H
/* The safety supervisor: command watchdog, E-stop, over-current, calibration gate and the
 * latched faults. It decides each control tick whether the output may run, must ramp to zero
 * (soft faults) or must be cut at once (hard faults). State machine: firmware/README.md. */
#include <stdbool.h>
#include <stdint.h>

#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_state_report.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CBX_RAMP_DOWN_MS 20u          /* soft faults: output reaches zero within this time */
#define CBX_OVERCURRENT_US 1000u      /* current over the limit this long: fault */

typedef enum {
  CBX_GATE_OFF = 0,  /* nothing to render (mode off, no command yet): output zero */
  CBX_GATE_RUN = 1,  /* render the command */
  CBX_GATE_RAMP = 2, /* soft fault (watchdog, encoder, bad command): ramp to zero */
  CBX_GATE_CUT = 3   /* hard fault (E-stop, over-current) or not calibrated: zero at once */
} cbx_gate;

typedef struct {
  uint16_t faults;             /* latched CBX_FAULT_* (NOT_CALIBRATED is never latched) */
  uint8_t armed;               /* a command with mode != off is in force: watchdog watching */
  uint8_t fresh;               /* the last valid command is within the watchdog timeout */
  uint8_t mode;                /* mode of the command in force */
  uint32_t last_command_us;
  uint32_t over_since_us[2];   /* start of the current over-limit run, per axis */
  uint8_t over[2];             /* currently over the limit */
} cbx_safety;

typedef struct {
  uint32_t now_us;
  bool estop_pressed;
  bool calibrated;
  bool encoder_error;          /* new illegal transitions since the last tick */
  int16_t current_mA[2];
} cbx_safety_inputs;

void cbx_safety_init(cbx_safety* s);
/* A valid command arrived: restarts the watchdog, (dis)arms it with the mode, and on
 * ACK_FAULTS clears the latched faults whose cause is gone. */
void cbx_safety_command(cbx_safety* s, uint32_t now_us, uint8_t mode, uint8_t flags,
                        const cbx_safety_inputs* in, const cbx_limits* limits);
/* A command failed to decode: latches BAD_COMMAND. */
void cbx_safety_bad_command(cbx_safety* s);
/* Once per control tick: updates faults from the inputs and returns the gate. */
cbx_gate cbx_safety_update(cbx_safety* s, const cbx_safety_inputs* in, const cbx_limits* limits);
/* The faults field of the state report (latched faults plus NOT_CALIBRATED). */
uint16_t cbx_safety_faults(const cbx_safety* s, bool calibrated);

#ifdef __cplusplus
}
#endif
#endif

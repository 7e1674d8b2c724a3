#include "firmware/cbx_safety.h"

#include "protocol/cbx_command_report.h"

/* Faults whose output reaction is an immediate cut; the others ramp down. */
#define HARD_FAULTS (CBX_FAULT_ESTOP | CBX_FAULT_OVERCURRENT)

void cbx_safety_init(cbx_safety* s) {
  s->faults = 0u;
  s->armed = 0u;
  s->fresh = 0u;
  s->mode = CBX_MODE_OFF;
  s->last_command_us = 0u;
  for (int i = 0; i < 2; ++i) {
    s->over_since_us[i] = 0u;
    s->over[i] = 0u;
  }
}

static bool current_over(int16_t current_mA, uint16_t limit_mA) {
  const int32_t c = current_mA < 0 ? -(int32_t)current_mA : current_mA;
  return c > (int32_t)limit_mA;
}

void cbx_safety_command(cbx_safety* s, uint32_t now_us, uint8_t mode, uint8_t flags,
                        const cbx_safety_inputs* in, const cbx_limits* limits) {
  s->last_command_us = now_us;
  s->fresh = 1u;
  s->mode = mode;
  /* A command with mode off is the host stopping on purpose: the watchdog stands down. */
  s->armed = (uint8_t)(mode != CBX_MODE_OFF);
  if (flags & CBX_CMD_ACK_FAULTS) {
    uint16_t keep = 0u;
    if (in->estop_pressed) keep |= CBX_FAULT_ESTOP;
    if (current_over(in->current_mA[0], limits->insertion_max_current_mA) ||
        current_over(in->current_mA[1], limits->rotation_max_current_mA))
      keep |= CBX_FAULT_OVERCURRENT;
    s->faults &= keep;
  }
}

void cbx_safety_bad_command(cbx_safety* s) { s->faults |= CBX_FAULT_BAD_COMMAND; }

cbx_gate cbx_safety_update(cbx_safety* s, const cbx_safety_inputs* in, const cbx_limits* limits) {
  if (in->estop_pressed) s->faults |= CBX_FAULT_ESTOP;
  if (in->encoder_error) s->faults |= CBX_FAULT_ENCODER;

  const uint16_t limit_mA[2] = {limits->insertion_max_current_mA, limits->rotation_max_current_mA};
  for (int i = 0; i < 2; ++i) {
    if (!current_over(in->current_mA[i], limit_mA[i])) {
      s->over[i] = 0u;
    } else if (!s->over[i]) {
      s->over[i] = 1u;
      s->over_since_us[i] = in->now_us;
    } else if (in->now_us - s->over_since_us[i] >= CBX_OVERCURRENT_US) {
      s->faults |= CBX_FAULT_OVERCURRENT;
    }
  }

  if (s->fresh && in->now_us - s->last_command_us >= (uint32_t)limits->watchdog_timeout_ms * 1000u) {
    s->fresh = 0u;
    if (s->armed) s->faults |= CBX_FAULT_WATCHDOG;
  }

  if ((s->faults & HARD_FAULTS) || !in->calibrated) return CBX_GATE_CUT;
  if (s->faults) return CBX_GATE_RAMP;
  if (!s->fresh || s->mode == CBX_MODE_OFF) return CBX_GATE_OFF;
  return CBX_GATE_RUN;
}

uint16_t cbx_safety_faults(const cbx_safety* s, bool calibrated) {
  return (uint16_t)(s->faults | (calibrated ? 0u : CBX_FAULT_NOT_CALIBRATED));
}

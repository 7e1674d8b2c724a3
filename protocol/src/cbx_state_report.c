#include "protocol/cbx_state_report.h"

#include "protocol/cbx_bytes.h"
#include "cbx_codec.h"

static cbx_status state_valid(const void* value) {
  const cbx_state_report* s = value;
  if ((s->status & ~CBX_STATUS_ALL) != 0u) return CBX_ERR_RANGE;
  if ((s->faults & ~CBX_FAULT_ALL) != 0u) return CBX_ERR_RANGE;
  if (s->mode > CBX_MODE_MOTOR) return CBX_ERR_RANGE;
  if ((s->board_faults & ~CBX_BOARD_FAULT_ALL) != 0u) return CBX_ERR_RANGE;
  return CBX_OK;
}

static void state_put(uint8_t* out, const void* value) {
  const cbx_state_report* s = value;
  cbx_put_i32(out + 8, s->insertion_count);
  cbx_put_i32(out + 12, s->rotation_count);
  cbx_put_i32(out + 16, s->insertion_vel_cps);
  cbx_put_i32(out + 20, s->rotation_vel_cps);
  cbx_put_i32(out + 24, s->insertion_force_mN);
  cbx_put_i32(out + 28, s->rotation_torque_uNm);
  cbx_put_i16(out + 32, s->insertion_current_mA);
  cbx_put_i16(out + 34, s->rotation_current_mA);
  cbx_put_u16(out + 36, s->status);
  cbx_put_u16(out + 38, s->faults);
  cbx_put_u16(out + 40, s->command_seq_echo);
  cbx_put_u16(out + 42, s->encoder_errors);
  cbx_put_u16(out + 44, s->rx_errors);
  cbx_put_u8(out + 46, s->mode);
  cbx_put_u8(out + 47, s->board_faults);
  cbx_put_u16(out + 48, s->in_dropped);
}

static void state_get(const uint8_t* in, void* value) {
  cbx_state_report* d = value;
  d->insertion_count = cbx_get_i32(in + 8);
  d->rotation_count = cbx_get_i32(in + 12);
  d->insertion_vel_cps = cbx_get_i32(in + 16);
  d->rotation_vel_cps = cbx_get_i32(in + 20);
  d->insertion_force_mN = cbx_get_i32(in + 24);
  d->rotation_torque_uNm = cbx_get_i32(in + 28);
  d->insertion_current_mA = cbx_get_i16(in + 32);
  d->rotation_current_mA = cbx_get_i16(in + 34);
  d->status = cbx_get_u16(in + 36);
  d->faults = cbx_get_u16(in + 38);
  d->command_seq_echo = cbx_get_u16(in + 40);
  d->encoder_errors = cbx_get_u16(in + 42);
  d->rx_errors = cbx_get_u16(in + 44);
  d->mode = cbx_get_u8(in + 46);
  d->board_faults = cbx_get_u8(in + 47);
  d->in_dropped = cbx_get_u16(in + 48);
}

static const cbx_codec kStateCodec = {CBX_ID_STATE, sizeof(cbx_state_report), state_valid,
                                      state_put, state_get};

cbx_status cbx_state_encode(const cbx_state_report* state, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kStateCodec, state, out);
}

cbx_status cbx_state_decode(const uint8_t* in, size_t length, cbx_state_report* state) {
  return cbx_codec_decode(&kStateCodec, in, length, state);
}

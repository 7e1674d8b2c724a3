#include "protocol/cbx_command_report.h"

#include "protocol/cbx_bytes.h"
#include "cbx_codec.h"

cbx_status cbx_force_law_check(const cbx_force_law* law) {
  if (law->stiffness < 0 || law->damping < 0) return CBX_ERR_RANGE;
  if (law->out_min > law->out_max) return CBX_ERR_RANGE;
  return CBX_OK;
}

/* coefficient * delta / 1e6 without overflow: |coefficient| < 2^31, |delta| < 2^33. */
static int64_t scaled_product(int32_t coefficient, int64_t delta) {
  const int64_t q = delta / 1000000;
  const int64_t r = delta % 1000000;
  return (int64_t)coefficient * q + ((int64_t)coefficient * r) / 1000000;
}

int32_t cbx_force_law_eval(const cbx_force_law* law, int32_t pos, int32_t vel) {
  /* Restoring and dissipative: with k, b >= 0 the law pushes back toward pos0 and against the
   * motion (a positive stiffness times a positive displacement pushes toward smaller positions). */
  int64_t out = (int64_t)law->offset - scaled_product(law->stiffness, (int64_t)pos - law->pos0) -
                scaled_product(law->damping, vel);
  if (out < law->out_min) out = law->out_min;
  if (out > law->out_max) out = law->out_max;
  return (int32_t)out;
}

static void put_law(uint8_t* p, const cbx_force_law* law) {
  cbx_put_i32(p + 0, law->offset);
  cbx_put_i32(p + 4, law->pos0);
  cbx_put_i32(p + 8, law->stiffness);
  cbx_put_i32(p + 12, law->damping);
  cbx_put_i32(p + 16, law->out_min);
  cbx_put_i32(p + 20, law->out_max);
}

static void get_law(const uint8_t* p, cbx_force_law* law) {
  law->offset = cbx_get_i32(p + 0);
  law->pos0 = cbx_get_i32(p + 4);
  law->stiffness = cbx_get_i32(p + 8);
  law->damping = cbx_get_i32(p + 12);
  law->out_min = cbx_get_i32(p + 16);
  law->out_max = cbx_get_i32(p + 20);
}

static cbx_status command_valid(const void* value) {
  const cbx_command_report* c = value;
  if (c->mode > CBX_MODE_MOTOR) return CBX_ERR_RANGE;
  if ((c->flags & ~CBX_CMD_ALL) != 0u) return CBX_ERR_RANGE;
  if (cbx_force_law_check(&c->insertion) != CBX_OK) return CBX_ERR_RANGE;
  return cbx_force_law_check(&c->rotation);
}

static void command_put(uint8_t* out, const void* value) {
  const cbx_command_report* c = value;
  cbx_put_u8(out + 8, c->mode);
  cbx_put_u8(out + 9, c->flags);
  put_law(out + 12, &c->insertion);
  put_law(out + 36, &c->rotation);
}

static void command_get(const uint8_t* in, void* value) {
  cbx_command_report* d = value;
  d->mode = cbx_get_u8(in + 8);
  d->flags = cbx_get_u8(in + 9);
  get_law(in + 12, &d->insertion);
  get_law(in + 36, &d->rotation);
}

static const cbx_codec kCommandCodec = {CBX_ID_COMMAND, sizeof(cbx_command_report),
                                        command_valid, command_put, command_get};

cbx_status cbx_command_encode(const cbx_command_report* command, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kCommandCodec, command, out);
}

cbx_status cbx_command_decode(const uint8_t* in, size_t length, cbx_command_report* command) {
  return cbx_codec_decode(&kCommandCodec, in, length, command);
}

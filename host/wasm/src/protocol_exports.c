/* cathbox-protocol.js: the box protocol's own encoder/decoder (protocol/, C11) for JavaScript,
 * the codec a WebHID page speaks the box with (no second implementation in JavaScript). The
 * reports cross as flat int32 field lists (order below; js/box_codec.js names them), and the
 * golden vectors are exported so that a test checks this build against them.
 *   state   (decoded):  version seq time_us insertion_count rotation_count insertion_vel_cps
 *                       rotation_vel_cps insertion_force_mN rotation_torque_uNm insertion_current_mA
 *                       rotation_current_mA status faults command_seq_echo encoder_errors rx_errors
 *                       mode board_faults in_dropped          (19 fields; encoded for tests too)
 *   command (encoded, and decoded for tests):  seq time_us mode flags, insertion law (offset pos0 stiffness damping
 *                       out_min out_max), rotation law (the same)                    (16 fields) */
#include <emscripten/emscripten.h>
#include <string.h>

#include "cbx_vectors.h"
#include "protocol/cbx_command_report.h"
#include "protocol/cbx_state_report.h"
#include "wasm/protocol_exports.h"

enum { STATE_FIELDS = 19, COMMAND_FIELDS = 16 };

static void state_fields(const cbx_state_report* s, int32_t* f) {
  const int32_t v[STATE_FIELDS] = {s->header.version, s->header.seq, (int32_t)s->header.time_us, s->insertion_count,
                                   s->rotation_count, s->insertion_vel_cps, s->rotation_vel_cps, s->insertion_force_mN,
                                   s->rotation_torque_uNm, s->insertion_current_mA, s->rotation_current_mA, s->status,
                                   s->faults, s->command_seq_echo, s->encoder_errors, s->rx_errors, s->mode,
                                   s->board_faults, s->in_dropped};
  memcpy(f, v, sizeof v);
}

static void law_fields(const cbx_force_law* law, int32_t* f) {
  f[0] = law->offset;
  f[1] = law->pos0;
  f[2] = law->stiffness;
  f[3] = law->damping;
  f[4] = law->out_min;
  f[5] = law->out_max;
}

static cbx_force_law law_from(const int32_t* f) {
  const cbx_force_law law = {f[0], f[1], f[2], f[3], f[4], f[5]};
  return law;
}

/* An IN report's bytes to its fields: CBX_OK, or the decoder's status (fields untouched). */
EMSCRIPTEN_KEEPALIVE int cbxw_state_decode(const uint8_t* in, size_t length, int32_t* fields) {
  cbx_state_report s;
  const cbx_status status = cbx_state_decode(in, length, &s);
  if (status == CBX_OK) state_fields(&s, fields);
  return status;
}

/* A state's fields to its 64 bytes (what a box sends: the tests' emulated WebHID device). */
EMSCRIPTEN_KEEPALIVE int cbxw_state_encode(const int32_t* f, uint8_t* out) {
  cbx_state_report s;
  memset(&s, 0, sizeof s);
  s.header.version = (uint8_t)f[0];
  s.header.seq = (uint16_t)f[1];
  s.header.time_us = (uint32_t)f[2];
  s.insertion_count = f[3];
  s.rotation_count = f[4];
  s.insertion_vel_cps = f[5];
  s.rotation_vel_cps = f[6];
  s.insertion_force_mN = f[7];
  s.rotation_torque_uNm = f[8];
  s.insertion_current_mA = (int16_t)f[9];
  s.rotation_current_mA = (int16_t)f[10];
  s.status = (uint16_t)f[11];
  s.faults = (uint16_t)f[12];
  s.command_seq_echo = (uint16_t)f[13];
  s.encoder_errors = (uint16_t)f[14];
  s.rx_errors = (uint16_t)f[15];
  s.mode = (uint8_t)f[16];
  s.board_faults = (uint8_t)f[17];
  s.in_dropped = (uint16_t)f[18];
  return cbx_state_encode(&s, out);
}

/* An OUT report's bytes to its fields (what a box receives: the tests' emulated device). */
EMSCRIPTEN_KEEPALIVE int cbxw_command_decode(const uint8_t* in, size_t length, int32_t* f) {
  cbx_command_report c;
  const cbx_status status = cbx_command_decode(in, length, &c);
  if (status != CBX_OK) return status;
  f[0] = c.header.seq;
  f[1] = (int32_t)c.header.time_us;
  f[2] = c.mode;
  f[3] = c.flags;
  law_fields(&c.insertion, f + 4);
  law_fields(&c.rotation, f + 10);
  return status;
}

/* A command's fields to its 64 bytes: CBX_OK, or the encoder's status (a law out of range). */
EMSCRIPTEN_KEEPALIVE int cbxw_command_encode(const int32_t* f, uint8_t* out) {
  cbx_command_report c;
  memset(&c, 0, sizeof c);
  c.header.version = CBX_PROTOCOL_VERSION;
  c.header.seq = (uint16_t)f[0];
  c.header.time_us = (uint32_t)f[1];
  c.mode = (uint8_t)f[2];
  c.flags = (uint8_t)f[3];
  c.insertion = law_from(f + 4);
  c.rotation = law_from(f + 10);
  return cbx_command_encode(&c, out);
}

EMSCRIPTEN_KEEPALIVE const char* cbxw_status_name(int status) { return cbx_status_name((cbx_status)status); }

/* The golden vectors (protocol/vectors). */
EMSCRIPTEN_KEEPALIVE int cbxw_vector_count(void) { return (int)cbx_vector_count; }
EMSCRIPTEN_KEEPALIVE const char* cbxw_vector_name(int i) { return cbx_vectors[i].name; }
EMSCRIPTEN_KEEPALIVE const char* cbxw_vector_kind(int i) { return cbx_vectors[i].kind; }
EMSCRIPTEN_KEEPALIVE int cbxw_vector_expect(int i) { return cbx_vectors[i].expect; }
EMSCRIPTEN_KEEPALIVE int cbxw_vector_length(int i) { return (int)cbx_vectors[i].length; }
EMSCRIPTEN_KEEPALIVE const uint8_t* cbxw_vector_bytes(int i) { return cbx_vectors[i].bytes; }
/* A state or command vector's value as the fields above (command: header seq/time first). */
EMSCRIPTEN_KEEPALIVE int cbxw_vector_fields(int i, int32_t* f) {
  const cbx_vector* v = &cbx_vectors[i];
  if (strcmp(v->kind, "state") == 0) {
    state_fields(&v->value.state, f);
    return STATE_FIELDS;
  }
  if (strcmp(v->kind, "command") == 0) {
    const cbx_command_report* c = &v->value.command;
    f[0] = c->header.seq;
    f[1] = (int32_t)c->header.time_us;
    f[2] = c->mode;
    f[3] = c->flags;
    law_fields(&c->insertion, f + 4);
    law_fields(&c->rotation, f + 10);
    return COMMAND_FIELDS;
  }
  return 0;
}
/* Every vector through this build's codec (cbx_vector_decode/encode): 0 when each good one
 * decodes and re-encodes to its bytes and each bad one is refused with its status. */
EMSCRIPTEN_KEEPALIVE int cbxw_vector_check(int i) {
  const cbx_vector* v = &cbx_vectors[i];
  cbx_vector decoded = *v;
  uint8_t out[CBX_REPORT_SIZE];
  memset(&decoded.value, 0xA5, sizeof decoded.value);
  const cbx_status status = cbx_vector_decode(v, &decoded.value);
  if (status != v->expect) return 1;
  if (status != CBX_OK) return 0;
  if (cbx_vector_encode(&decoded, out) != CBX_OK) return 2;
  return memcmp(out, v->bytes, CBX_REPORT_SIZE) == 0 ? 0 : 3;
}

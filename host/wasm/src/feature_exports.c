/* cathbox-protocol.js, continued: the feature reports a page reads from the box on connect
 * (device info 0x10, calibration 0x11, limits 0x12; protocol/README.md), through protocol/'s own
 * codec, as flat int32 field lists (js/box_codec.js names them; u32 fields cross as int32 and are
 * read back unsigned). Each list starts with the header: version seq time_us.
 *   device info  (11): header, fw_major fw_minor fw_patch protocol_minor insertion_actuator
 *                      rotation_actuator insertion_encoder_cpr rotation_encoder_cpr; its text
 *                      (serial, board, build) NUL-terminated at text + 0, 17 and 34
 *   calibration  (23): header, insertion_counts_per_m rotation_counts_per_rev
 *                      insertion_full_scale_mN rotation_full_scale_uNm, insertion curve
 *                      (in out) x 4, rotation curve (in out) x 4
 *   limits       (10): header, max_force_mN max_torque_uNm watchdog_timeout_ms
 *                      insertion_max_current_mA rotation_max_current_mA force_slew_mN_per_ms
 *                      torque_slew_uNm_per_ms
 * The encoders (what a box answers) serve the tests' emulated WebHID device. */
#include <emscripten/emscripten.h>
#include <string.h>

#include "cbx_vectors.h"
#include "protocol/cbx_feature_reports.h"
#include "wasm/protocol_exports.h"

enum { TEXT_STRIDE = CBX_TEXT_FIELD + 1 };

static void header_fields(const cbx_header* h, int32_t* f) {
  f[0] = h->version;
  f[1] = h->seq;
  f[2] = (int32_t)h->time_us;
}

static cbx_header header_from(const int32_t* f) {
  const cbx_header h = {(uint8_t)f[0], (uint16_t)f[1], (uint32_t)f[2]};
  return h;
}

static void device_info_fields(const cbx_device_info* v, int32_t* f, char* text) {
  header_fields(&v->header, f);
  const int32_t rest[8] = {v->fw_major, v->fw_minor, v->fw_patch, v->protocol_minor, v->insertion_actuator,
                           v->rotation_actuator, (int32_t)v->insertion_encoder_cpr, (int32_t)v->rotation_encoder_cpr};
  memcpy(f + 3, rest, sizeof rest);
  memcpy(text, v->serial, TEXT_STRIDE);
  memcpy(text + TEXT_STRIDE, v->board, TEXT_STRIDE);
  memcpy(text + 2 * TEXT_STRIDE, v->build, CBX_BUILD_FIELD + 1);
}

static void calibration_fields(const cbx_calibration* v, int32_t* f) {
  header_fields(&v->header, f);
  f[3] = (int32_t)v->insertion_counts_per_m;
  f[4] = (int32_t)v->rotation_counts_per_rev;
  f[5] = (int32_t)v->insertion_full_scale_mN;
  f[6] = (int32_t)v->rotation_full_scale_uNm;
  for (unsigned i = 0; i < CBX_CURVE_POINTS; ++i) {
    f[7 + 2 * i] = v->insertion_curve[i].in_permille;
    f[8 + 2 * i] = v->insertion_curve[i].out_permille;
    f[15 + 2 * i] = v->rotation_curve[i].in_permille;
    f[16 + 2 * i] = v->rotation_curve[i].out_permille;
  }
}

static void limits_fields(const cbx_limits* v, int32_t* f) {
  header_fields(&v->header, f);
  const int32_t rest[7] = {(int32_t)v->max_force_mN, (int32_t)v->max_torque_uNm, v->watchdog_timeout_ms,
                           v->insertion_max_current_mA, v->rotation_max_current_mA, v->force_slew_mN_per_ms,
                           v->torque_slew_uNm_per_ms};
  memcpy(f + 3, rest, sizeof rest);
}

/* A feature report's bytes (its ID at byte 0) to its fields: CBX_OK or the decoder's status. */
EMSCRIPTEN_KEEPALIVE int cbxw_feature_decode(int id, const uint8_t* in, size_t length, int32_t* f, char* text) {
  if (id == CBX_ID_DEVICE_INFO) {
    cbx_device_info v;
    const cbx_status status = cbx_device_info_decode(in, length, &v);
    if (status == CBX_OK) device_info_fields(&v, f, text);
    return status;
  }
  if (id == CBX_ID_CALIBRATION) {
    cbx_calibration v;
    const cbx_status status = cbx_calibration_decode(in, length, &v);
    if (status == CBX_OK) calibration_fields(&v, f);
    return status;
  }
  if (id == CBX_ID_LIMITS) {
    cbx_limits v;
    const cbx_status status = cbx_limits_decode(in, length, &v);
    if (status == CBX_OK) limits_fields(&v, f);
    return status;
  }
  return CBX_ERR_REPORT_ID;
}

/* Fields (and, for device info, its text) to a feature report's 64 bytes: CBX_OK or the
 * encoder's status. */
EMSCRIPTEN_KEEPALIVE int cbxw_feature_encode(int id, const int32_t* f, const char* text, uint8_t* out) {
  if (id == CBX_ID_DEVICE_INFO) {
    cbx_device_info v;
    memset(&v, 0, sizeof v);
    v.header = header_from(f);
    v.fw_major = (uint8_t)f[3];
    v.fw_minor = (uint8_t)f[4];
    v.fw_patch = (uint8_t)f[5];
    v.protocol_minor = (uint8_t)f[6];
    v.insertion_actuator = (uint8_t)f[7];
    v.rotation_actuator = (uint8_t)f[8];
    v.insertion_encoder_cpr = (uint32_t)f[9];
    v.rotation_encoder_cpr = (uint32_t)f[10];
    memcpy(v.serial, text, CBX_TEXT_FIELD);
    memcpy(v.board, text + TEXT_STRIDE, CBX_TEXT_FIELD);
    memcpy(v.build, text + 2 * TEXT_STRIDE, CBX_BUILD_FIELD);
    return cbx_device_info_encode(&v, out);
  }
  if (id == CBX_ID_CALIBRATION) {
    cbx_calibration v;
    memset(&v, 0, sizeof v);
    v.header = header_from(f);
    v.insertion_counts_per_m = (uint32_t)f[3];
    v.rotation_counts_per_rev = (uint32_t)f[4];
    v.insertion_full_scale_mN = (uint32_t)f[5];
    v.rotation_full_scale_uNm = (uint32_t)f[6];
    for (unsigned i = 0; i < CBX_CURVE_POINTS; ++i) {
      v.insertion_curve[i].in_permille = (uint16_t)f[7 + 2 * i];
      v.insertion_curve[i].out_permille = (uint16_t)f[8 + 2 * i];
      v.rotation_curve[i].in_permille = (uint16_t)f[15 + 2 * i];
      v.rotation_curve[i].out_permille = (uint16_t)f[16 + 2 * i];
    }
    return cbx_calibration_encode(&v, out);
  }
  if (id == CBX_ID_LIMITS) {
    cbx_limits v;
    memset(&v, 0, sizeof v);
    v.header = header_from(f);
    v.max_force_mN = (uint32_t)f[3];
    v.max_torque_uNm = (uint32_t)f[4];
    v.watchdog_timeout_ms = (uint16_t)f[5];
    v.insertion_max_current_mA = (uint16_t)f[6];
    v.rotation_max_current_mA = (uint16_t)f[7];
    v.force_slew_mN_per_ms = (uint16_t)f[8];
    v.torque_slew_uNm_per_ms = (uint16_t)f[9];
    return cbx_limits_encode(&v, out);
  }
  return CBX_ERR_REPORT_ID;
}

/* A device info, calibration or limits vector's value as the fields above; 0 for other kinds. */
EMSCRIPTEN_KEEPALIVE int cbxw_vector_feature_fields(int i, int32_t* f, char* text) {
  const cbx_vector* v = &cbx_vectors[i];
  if (strcmp(v->kind, "device_info") == 0) {
    device_info_fields(&v->value.device_info, f, text);
    return 11;
  }
  if (strcmp(v->kind, "calibration") == 0) {
    calibration_fields(&v->value.calibration, f);
    return 23;
  }
  if (strcmp(v->kind, "limits") == 0) {
    limits_fields(&v->value.limits, f);
    return 10;
  }
  return 0;
}

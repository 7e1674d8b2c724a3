#include "protocol/cbx_bytes.h"
#include "cbx_codec.h"
#include "cbx_text.h"
#include "protocol/cbx_feature_reports.h"

static cbx_status info_valid(const void* value) {
  const cbx_device_info* v = value;
  if (v->insertion_actuator > CBX_ACTUATOR_MOTOR || v->rotation_actuator > CBX_ACTUATOR_MOTOR)
    return CBX_ERR_RANGE;
  if (!cbx_text_valid(v->serial, CBX_TEXT_FIELD) || !cbx_text_valid(v->board, CBX_TEXT_FIELD) ||
      !cbx_text_valid(v->build, CBX_BUILD_FIELD))
    return CBX_ERR_RANGE;
  return CBX_OK;
}

static void info_put(uint8_t* out, const void* value) {
  const cbx_device_info* v = value;
  cbx_put_u8(out + 8, v->fw_major);
  cbx_put_u8(out + 9, v->fw_minor);
  cbx_put_u8(out + 10, v->fw_patch);
  cbx_put_u8(out + 11, v->protocol_minor);
  cbx_put_text(out + 12, v->serial, CBX_TEXT_FIELD);
  cbx_put_text(out + 28, v->board, CBX_TEXT_FIELD);
  cbx_put_u8(out + 44, v->insertion_actuator);
  cbx_put_u8(out + 45, v->rotation_actuator);
  cbx_put_u32(out + 46, v->insertion_encoder_cpr);
  cbx_put_u32(out + 50, v->rotation_encoder_cpr);
  cbx_put_text(out + 54, v->build, CBX_BUILD_FIELD);
}

static void info_get(const uint8_t* in, void* value) {
  cbx_device_info* v = value;
  v->fw_major = cbx_get_u8(in + 8);
  v->fw_minor = cbx_get_u8(in + 9);
  v->fw_patch = cbx_get_u8(in + 10);
  v->protocol_minor = cbx_get_u8(in + 11);
  cbx_text_get(in + 12, v->serial, CBX_TEXT_FIELD);
  cbx_text_get(in + 28, v->board, CBX_TEXT_FIELD);
  v->insertion_actuator = cbx_get_u8(in + 44);
  v->rotation_actuator = cbx_get_u8(in + 45);
  v->insertion_encoder_cpr = cbx_get_u32(in + 46);
  v->rotation_encoder_cpr = cbx_get_u32(in + 50);
  cbx_text_get(in + 54, v->build, CBX_BUILD_FIELD);
}

static const cbx_codec kInfoCodec = {CBX_ID_DEVICE_INFO, sizeof(cbx_device_info), info_valid,
                                     info_put, info_get};

cbx_status cbx_device_info_encode(const cbx_device_info* v, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kInfoCodec, v, out);
}
cbx_status cbx_device_info_decode(const uint8_t* in, size_t length, cbx_device_info* v) {
  return cbx_codec_decode(&kInfoCodec, in, length, v);
}

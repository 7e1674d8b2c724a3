#include <string.h>

#include "protocol/cbx_bytes.h"
#include "protocol/cbx_crc16.h"
#include "protocol/cbx_protocol.h"

const char* cbx_status_name(cbx_status status) {
  switch (status) {
    case CBX_OK: return "ok";
    case CBX_ERR_NULL: return "null pointer";
    case CBX_ERR_LENGTH: return "wrong length";
    case CBX_ERR_REPORT_ID: return "wrong report id";
    case CBX_ERR_VERSION: return "incompatible protocol version";
    case CBX_ERR_CRC: return "crc mismatch";
    case CBX_ERR_RANGE: return "value out of range";
    case CBX_ERR_STATE: return "not acceptable in this state";
  }
  return "unknown status";
}

int cbx_report_peek_id(const uint8_t* report, size_t length) {
  if (report == NULL) return CBX_ERR_NULL;
  if (length != CBX_REPORT_SIZE) return CBX_ERR_LENGTH;
  return report[0];
}

cbx_status cbx_report_check(const uint8_t* report, size_t length, uint8_t expected_id) {
  if (report == NULL) return CBX_ERR_NULL;
  if (length != CBX_REPORT_SIZE) return CBX_ERR_LENGTH;
  if (report[0] != expected_id) return CBX_ERR_REPORT_ID;
  if (report[1] != CBX_PROTOCOL_VERSION) return CBX_ERR_VERSION;
  if (cbx_crc16(report, CBX_CRC_OFFSET) != cbx_get_u16(report + CBX_CRC_OFFSET)) return CBX_ERR_CRC;
  return CBX_OK;
}

void cbx_report_begin(uint8_t report[CBX_REPORT_SIZE], uint8_t id, const cbx_header* header) {
  memset(report, 0, CBX_REPORT_SIZE);
  report[0] = id;
  report[1] = CBX_PROTOCOL_VERSION;
  cbx_put_u16(report + 2, header->seq);
  cbx_put_u32(report + 4, header->time_us);
}

void cbx_report_finish(uint8_t report[CBX_REPORT_SIZE]) {
  cbx_put_u16(report + CBX_CRC_OFFSET, cbx_crc16(report, CBX_CRC_OFFSET));
}

void cbx_report_read_header(const uint8_t report[CBX_REPORT_SIZE], cbx_header* header) {
  header->version = report[1];
  header->seq = cbx_get_u16(report + 2);
  header->time_us = cbx_get_u32(report + 4);
}

#include "cbx_codec.h"

#define CBX_CODEC_SCRATCH 128u

cbx_status cbx_codec_encode(const cbx_codec* codec, const void* value, uint8_t* out) {
  if (value == NULL || out == NULL) return CBX_ERR_NULL;
  const cbx_status valid = codec->valid(value);
  if (valid != CBX_OK) return valid;
  cbx_report_begin(out, codec->id, (const cbx_header*)value);
  codec->put(out, value);
  cbx_report_finish(out);
  return CBX_OK;
}

cbx_status cbx_codec_decode(const cbx_codec* codec, const uint8_t* in, size_t length, void* value) {
  if (value == NULL) return CBX_ERR_NULL;
  const cbx_status checked = cbx_report_check(in, length, codec->id);
  if (checked != CBX_OK) return checked;
  _Alignas(8) unsigned char scratch[CBX_CODEC_SCRATCH];
  if (codec->value_size > sizeof scratch) return CBX_ERR_STATE;
  memset(scratch, 0, sizeof scratch);
  cbx_report_read_header(in, (cbx_header*)(void*)scratch);
  codec->get(in, scratch);
  const cbx_status valid = codec->valid(scratch);
  if (valid != CBX_OK) return valid;
  memcpy(value, scratch, codec->value_size);
  return CBX_OK;
}

#include "protocol/cbx_image_info.h"

#include <string.h>

#include "protocol/cbx_bytes.h"
#include "cbx_text.h"

/* Offsets in the block. */
#define AT_MAGIC 0u
#define AT_LAYOUT 4u
#define AT_SIZE 5u
#define AT_VERSION 6u /* major, minor, patch, protocol minor */
#define AT_BOARD 12u
#define AT_BUILD 28u
#define AT_IMAGE_SIZE 60u

static cbx_status info_valid(const cbx_image_info* v) {
  if (!cbx_text_valid(v->board, CBX_TEXT_FIELD) || v->board[0] == '\0') return CBX_ERR_RANGE;
  if (!cbx_text_valid(v->build, CBX_BUILD_FIELD)) return CBX_ERR_RANGE;
  if (v->image_size < CBX_IMAGE_INFO_OFFSET + CBX_IMAGE_INFO_SIZE || v->image_size > CBX_IMAGE_MAX_SIZE)
    return CBX_ERR_RANGE;
  return CBX_OK;
}

cbx_status cbx_image_info_decode(const uint8_t* in, size_t length, cbx_image_info* out) {
  if (in == NULL || out == NULL) return CBX_ERR_NULL;
  if (length < CBX_IMAGE_INFO_SIZE) return CBX_ERR_LENGTH;
  if (cbx_get_u32(in + AT_MAGIC) != CBX_IMAGE_INFO_MAGIC) return CBX_ERR_REPORT_ID;
  if (in[AT_LAYOUT] != CBX_IMAGE_INFO_LAYOUT || in[AT_SIZE] != CBX_IMAGE_INFO_SIZE) return CBX_ERR_VERSION;
  cbx_image_info v;
  memset(&v, 0, sizeof v);
  v.fw_major = in[AT_VERSION];
  v.fw_minor = in[AT_VERSION + 1u];
  v.fw_patch = in[AT_VERSION + 2u];
  v.protocol_minor = in[AT_VERSION + 3u];
  cbx_text_get(in + AT_BOARD, v.board, CBX_TEXT_FIELD);
  cbx_text_get(in + AT_BUILD, v.build, CBX_BUILD_FIELD);
  v.image_size = cbx_get_u32(in + AT_IMAGE_SIZE);
  const cbx_status st = info_valid(&v);
  if (st != CBX_OK) return st;
  *out = v;
  return CBX_OK;
}

cbx_status cbx_image_info_encode(const cbx_image_info* info, uint8_t out[CBX_IMAGE_INFO_SIZE]) {
  if (info == NULL || out == NULL) return CBX_ERR_NULL;
  const cbx_status st = info_valid(info);
  if (st != CBX_OK) return st;
  memset(out, 0, CBX_IMAGE_INFO_SIZE);
  cbx_put_u32(out + AT_MAGIC, CBX_IMAGE_INFO_MAGIC);
  out[AT_LAYOUT] = CBX_IMAGE_INFO_LAYOUT;
  out[AT_SIZE] = CBX_IMAGE_INFO_SIZE;
  out[AT_VERSION] = info->fw_major;
  out[AT_VERSION + 1u] = info->fw_minor;
  out[AT_VERSION + 2u] = info->fw_patch;
  out[AT_VERSION + 3u] = info->protocol_minor;
  cbx_put_text(out + AT_BOARD, info->board, CBX_TEXT_FIELD);
  cbx_put_text(out + AT_BUILD, info->build, CBX_BUILD_FIELD);
  cbx_put_u32(out + AT_IMAGE_SIZE, info->image_size);
  return CBX_OK;
}

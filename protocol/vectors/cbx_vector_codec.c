/* Dispatch from a vector's kind to the protocol's decoder and encoder. */
#include <string.h>

#include "cbx_vectors.h"

typedef cbx_status (*decode_fn)(const uint8_t*, size_t, void*);
typedef cbx_status (*encode_fn)(const void*, uint8_t*);

typedef struct {
  const char* kind;
  decode_fn decode;
  encode_fn encode;
} codec_entry;

#define CBX_ENTRY(kind) {#kind, (decode_fn)cbx_##kind##_decode, (encode_fn)cbx_##kind##_encode}

static const codec_entry kCodecs[] = {
    {"state", (decode_fn)cbx_state_decode, (encode_fn)cbx_state_encode},
    {"command", (decode_fn)cbx_command_decode, (encode_fn)cbx_command_encode},
    CBX_ENTRY(device_info),
    CBX_ENTRY(calibration),
    CBX_ENTRY(limits),
    CBX_ENTRY(reset_counters),
    CBX_ENTRY(enter_bootloader),
    CBX_ENTRY(selftest),
};

static const codec_entry* find(const char* kind) {
  for (size_t i = 0; i < sizeof kCodecs / sizeof kCodecs[0]; ++i) {
    if (strcmp(kCodecs[i].kind, kind) == 0) return &kCodecs[i];
  }
  return NULL;
}

cbx_status cbx_vector_decode(const cbx_vector* vector, void* out) {
  const codec_entry* codec = find(vector->kind);
  if (codec == NULL) return CBX_ERR_REPORT_ID;
  return codec->decode(vector->bytes, vector->length, out);
}

cbx_status cbx_vector_encode(const cbx_vector* vector, uint8_t out[CBX_REPORT_SIZE]) {
  const codec_entry* codec = find(vector->kind);
  if (codec == NULL) return CBX_ERR_REPORT_ID;
  return codec->encode(&vector->value, out);
}

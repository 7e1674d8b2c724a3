#ifndef CBX_CODEC_H
#define CBX_CODEC_H
/* The one encode/decode path shared by every report kind (private to protocol/).
 * Each report struct starts with its cbx_header; a codec names the report ID, a range check
 * and the body's put/get functions. Decoding writes the caller's struct only on success. */
#include "protocol/cbx_protocol.h"

typedef struct {
  uint8_t id;
  size_t value_size;                              /* sizeof the report struct, <= 128 */
  cbx_status (*valid)(const void* value);         /* range check of the decoded fields */
  void (*put)(uint8_t* report, const void* value);/* body bytes 8..61 */
  void (*get)(const uint8_t* report, void* value);
} cbx_codec;

cbx_status cbx_codec_encode(const cbx_codec* codec, const void* value, uint8_t* out);
cbx_status cbx_codec_decode(const cbx_codec* codec, const uint8_t* in, size_t length, void* value);
#endif

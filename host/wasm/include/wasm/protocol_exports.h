#ifndef CBX_WASM_PROTOCOL_EXPORTS_H
#define CBX_WASM_PROTOCOL_EXPORTS_H
/* cathbox-protocol.js's C functions (src/protocol_exports.c): protocol/'s codec and golden
 * vectors for JavaScript (js/box_codec.js). Fields as the source file lists them. */
#include <stddef.h>
#include <stdint.h>

int cbxw_state_decode(const uint8_t* in, size_t length, int32_t* fields);
int cbxw_command_encode(const int32_t* fields, uint8_t* out);
int cbxw_state_encode(const int32_t* fields, uint8_t* out);
int cbxw_command_decode(const uint8_t* in, size_t length, int32_t* fields);
const char* cbxw_status_name(int status);
int cbxw_vector_count(void);
const char* cbxw_vector_name(int i);
const char* cbxw_vector_kind(int i);
int cbxw_vector_expect(int i);
int cbxw_vector_length(int i);
const uint8_t* cbxw_vector_bytes(int i);
int cbxw_vector_fields(int i, int32_t* fields);
int cbxw_vector_check(int i);
/* The feature reports (src/feature_exports.c). */
int cbxw_feature_decode(int id, const uint8_t* in, size_t length, int32_t* fields, char* text);
int cbxw_feature_encode(int id, const int32_t* fields, const char* text, uint8_t* out);
int cbxw_vector_feature_fields(int i, int32_t* fields, char* text);

#endif

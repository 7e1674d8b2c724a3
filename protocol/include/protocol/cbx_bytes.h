#ifndef CBX_BYTES_H
#define CBX_BYTES_H
/* Little-endian field access: the one way every part of Cathbox (protocol codecs, firmware,
 * emulator, host DFU/flash code) reads and writes a multi-byte field in a byte buffer. Two's
 * complement for signed types. C11, header-only, usable from C++. Spec: protocol/README.md,
 * "Byte order". */
#include <stddef.h>
#include <stdint.h>

static inline void cbx_put_u8(uint8_t* p, uint8_t v) { p[0] = v; }
static inline void cbx_put_u16(uint8_t* p, uint16_t v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)(v >> 8);
}
/* 24-bit field (the low three bytes of v), e.g. DFU bwPollTimeout. */
static inline void cbx_put_u24(uint8_t* p, uint32_t v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)((v >> 8) & 0xFFu);
  p[2] = (uint8_t)((v >> 16) & 0xFFu);
}
static inline void cbx_put_u32(uint8_t* p, uint32_t v) {
  cbx_put_u24(p, v);
  p[3] = (uint8_t)(v >> 24);
}
static inline void cbx_put_u64(uint8_t* p, uint64_t v) {
  cbx_put_u32(p, (uint32_t)(v & 0xFFFFFFFFu));
  cbx_put_u32(p + 4, (uint32_t)(v >> 32));
}
static inline void cbx_put_i16(uint8_t* p, int16_t v) { cbx_put_u16(p, (uint16_t)v); }
static inline void cbx_put_i32(uint8_t* p, int32_t v) { cbx_put_u32(p, (uint32_t)v); }

static inline uint8_t cbx_get_u8(const uint8_t* p) { return p[0]; }
static inline uint16_t cbx_get_u16(const uint8_t* p) {
  return (uint16_t)((uint16_t)p[0] | (uint16_t)((uint16_t)p[1] << 8));
}
static inline uint32_t cbx_get_u24(const uint8_t* p) {
  return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16);
}
static inline uint32_t cbx_get_u32(const uint8_t* p) { return cbx_get_u24(p) | ((uint32_t)p[3] << 24); }
static inline uint64_t cbx_get_u64(const uint8_t* p) {
  return (uint64_t)cbx_get_u32(p) | ((uint64_t)cbx_get_u32(p + 4) << 32);
}
/* Two's complement reinterpretation without implementation-defined conversions. */
static inline int16_t cbx_get_i16(const uint8_t* p) {
  const uint16_t u = cbx_get_u16(p);
  return u <= 0x7FFFu ? (int16_t)u : (int16_t)(-(int32_t)(0xFFFFu - u) - 1);
}
static inline int32_t cbx_get_i32(const uint8_t* p) {
  const uint32_t u = cbx_get_u32(p);
  return u <= 0x7FFFFFFFu ? (int32_t)u : (int32_t)(-(int64_t)(0xFFFFFFFFu - u) - 1);
}
/* Fixed-width ASCII text, NUL-padded; the decoded copy is always NUL-terminated. */
static inline void cbx_put_text(uint8_t* p, const char* text, size_t width) {
  size_t i = 0;
  for (; i < width && text[i] != '\0'; ++i) p[i] = (uint8_t)text[i];
  for (; i < width; ++i) p[i] = 0;
}
#endif

#ifndef CBX_TEXT_H
#define CBX_TEXT_H
/* Fixed-width ASCII text fields (private to protocol/): printable ASCII 0x20..0x7E, then only
 * NUL padding. Used by the device info report and the firmware image info block. */
#include <stddef.h>
#include <stdint.h>

/* Printable ASCII up to the first NUL (or `width`). */
static inline int cbx_text_valid(const char* text, size_t width) {
  for (size_t i = 0; i < width && text[i] != '\0'; ++i) {
    if (text[i] < 0x20 || text[i] > 0x7E) return 0;
  }
  return 1;
}

/* Copies a field into text[0..width] (NUL-terminated); a byte after the padding started makes
 * the copy invalid for cbx_text_valid (its first byte becomes 0x01). */
static inline void cbx_text_get(const uint8_t* p, char* text, size_t width) {
  int ended = 0, stray = 0;
  for (size_t i = 0; i < width; ++i) {
    if (p[i] == 0) ended = 1;
    else if (ended) stray = 1;
    text[i] = ended ? '\0' : (char)p[i];
  }
  text[width] = '\0';
  if (stray) text[0] = (char)0x01;
}
#endif

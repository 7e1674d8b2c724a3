#ifndef CBX_IMAGE_INFO_H
#define CBX_IMAGE_INFO_H
/* The firmware image info block: 64 bytes at offset CBX_IMAGE_INFO_OFFSET of every Cathbox
 * firmware image (right after the Cortex-M vector table), saying what the image is. Written by
 * the firmware build (ports/<board>/image_info.c and the linker script), read from the flashed
 * bytes by the emulator and the host tools. Layout in protocol/README.md. */
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CBX_IMAGE_INFO_OFFSET 0x200u     /* from the start of the image (flash 0x08000200) */
#define CBX_IMAGE_INFO_SIZE 64u
#define CBX_IMAGE_INFO_MAGIC 0x49584243u /* "CBXI", little-endian at bytes 0..3 */
#define CBX_IMAGE_INFO_LAYOUT 1u
#define CBX_IMAGE_MAX_SIZE (512u * 1024u)

typedef struct {
  uint8_t fw_major, fw_minor, fw_patch;
  uint8_t protocol_minor;           /* minor of protocol v(fw_major) the image implements */
  char board[CBX_TEXT_FIELD + 1];   /* the board the image was built for, e.g. "stm32f411-bp" */
  char build[CBX_BUILD_FIELD + 1];  /* build identifier, e.g. the short commit */
  uint32_t image_size;              /* bytes from the start of the image to its end */
} cbx_image_info;

/* Reads the block from `in` (at least CBX_IMAGE_INFO_SIZE bytes: the image from offset
 * CBX_IMAGE_INFO_OFFSET). CBX_ERR_LENGTH if shorter, CBX_ERR_REPORT_ID for a wrong magic,
 * CBX_ERR_VERSION for another layout or block size, CBX_ERR_RANGE for bad text, an empty board
 * or an image size outside (offset + 64, CBX_IMAGE_MAX_SIZE]. `out` is written only on success. */
cbx_status cbx_image_info_decode(const uint8_t* in, size_t length, cbx_image_info* out);
/* Writes the 64-byte block; the same checks as decoding. */
cbx_status cbx_image_info_encode(const cbx_image_info* info, uint8_t out[CBX_IMAGE_INFO_SIZE]);

#ifdef __cplusplus
}
#endif
#endif

/* The image info block (protocol/README.md, "Firmware image info block"): 64 bytes at image
 * offset 0x200, right after the vector table. stm32f411ce.ld places this section there and
 * appends the image size as the block's last four bytes. The emulator reads the block from the
 * flashed image (a box whose image has none stays in the bootloader); `cathbox` reads it from
 * image files; the firmware reports the same version and build in its device info. */
#include <stddef.h>

#include "board.h"
#include "cbx_build_id.h"
#include "protocol/cbx_image_info.h"

/* Bytes 0..59 of the block. Every member is made of bytes, so there is no padding and no byte
 * order to choose; the magic is spelt out little-endian. */
typedef struct {
  uint8_t magic[4];
  uint8_t layout;
  uint8_t size;
  uint8_t version[4]; /* major, minor, patch, protocol minor */
  uint8_t reserved0[2];
  char board[CBX_TEXT_FIELD];
  char build[CBX_BUILD_FIELD];
  uint8_t reserved1[24];
} image_info_head;

_Static_assert(offsetof(image_info_head, board) == 12u, "board at block byte 12");
_Static_assert(offsetof(image_info_head, build) == 28u, "build at block byte 28");
_Static_assert(sizeof(image_info_head) == CBX_IMAGE_INFO_SIZE - 4u, "the linker adds the image size");
_Static_assert(sizeof CBX_BUILD_ID - 1u <= CBX_BUILD_FIELD, "build identifier too long");
_Static_assert(sizeof CBX_BOARD_NAME - 1u <= CBX_TEXT_FIELD, "board name too long");

__attribute__((section(".image_info"), used)) const image_info_head cbx_image_info_head = {
    {(uint8_t)(CBX_IMAGE_INFO_MAGIC & 0xFFu), (uint8_t)((CBX_IMAGE_INFO_MAGIC >> 8) & 0xFFu),
     (uint8_t)((CBX_IMAGE_INFO_MAGIC >> 16) & 0xFFu), (uint8_t)(CBX_IMAGE_INFO_MAGIC >> 24)},
    CBX_IMAGE_INFO_LAYOUT,
    CBX_IMAGE_INFO_SIZE,
    {CBX_FW_MAJOR, CBX_FW_MINOR, CBX_FW_PATCH, CBX_PROTOCOL_MINOR},
    {0u, 0u},
    CBX_BOARD_NAME,
    CBX_BUILD_ID,
    {0u},
};

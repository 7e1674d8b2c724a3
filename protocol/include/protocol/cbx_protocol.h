#ifndef CBX_PROTOCOL_H
#define CBX_PROTOCOL_H
/* Cathbox box <-> host protocol v1: constants, status codes and the common report header.
 * Every report is 64 bytes on the wire: a report ID byte and a 63-byte payload, so each
 * interrupt transfer is one full-speed packet. Multi-byte fields are little-endian and are
 * encoded and decoded by explicit functions only. See protocol/README.md. */
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CBX_PROTOCOL_VERSION 1u       /* major: byte 1 of every report; a mismatch is incompatible */
#define CBX_PROTOCOL_MINOR 1u         /* minor: in the device info report; additions only */
#define CBX_REPORT_SIZE 64u           /* report ID + 63-byte payload */
#define CBX_HEADER_SIZE 8u            /* id, version, seq (2), time_us (4) */
#define CBX_CRC_OFFSET 62u            /* CRC-16/CCITT-FALSE over bytes 0..61, little-endian */

#define CBX_USB_VID 0x1209u           /* pid.codes shared VID for open hardware */
#define CBX_USB_PID 0xCB01u           /* Cathbox (provisional) */
#define CBX_DFU_VID 0x0483u           /* STM32 ROM DFU bootloader */
#define CBX_DFU_PID 0xDF11u

/* Report IDs (byte 0). */
typedef enum {
  CBX_ID_STATE = 0x01,           /* IN, 1 kHz: box state */
  CBX_ID_COMMAND = 0x02,         /* OUT, 1 kHz: mode and local force laws */
  CBX_ID_DEVICE_INFO = 0x10,     /* feature get */
  CBX_ID_CALIBRATION = 0x11,     /* feature get / set */
  CBX_ID_LIMITS = 0x12,          /* feature get / set */
  CBX_ID_RESET_COUNTERS = 0x13,  /* feature set */
  CBX_ID_ENTER_BOOTLOADER = 0x14,/* feature set */
  CBX_ID_SELFTEST = 0x15         /* feature get (result) / set (start) */
} cbx_report_id;

/* Results of every encoder and decoder. Bad input is an error return, never an assert. */
typedef enum {
  CBX_OK = 0,
  CBX_ERR_NULL = -1,       /* a required pointer was NULL */
  CBX_ERR_LENGTH = -2,     /* the buffer is not exactly CBX_REPORT_SIZE bytes */
  CBX_ERR_REPORT_ID = -3,  /* byte 0 is not the report ID this function handles */
  CBX_ERR_VERSION = -4,    /* byte 1 is not CBX_PROTOCOL_VERSION: incompatible peer */
  CBX_ERR_CRC = -5,        /* bytes 62..63 do not match the CRC of bytes 0..61 */
  CBX_ERR_RANGE = -6,      /* a field holds a value outside its documented range */
  CBX_ERR_STATE = -7       /* well-formed, but not acceptable now (used by firmware/host) */
} cbx_status;

/* Common header of every report (bytes 1..7; byte 0 is the report ID). */
typedef struct {
  uint8_t version;  /* CBX_PROTOCOL_VERSION when encoding; checked when decoding */
  uint16_t seq;     /* sender's sequence number, +1 per report of this kind, wrapping */
  uint32_t time_us; /* sender's clock in microseconds, wrapping at 2^32 */
} cbx_header;

/* A short, stable name for a status ("ok", "crc", ...). */
const char* cbx_status_name(cbx_status status);

/* Report ID of a received report after checking only its length: the first step of dispatch.
 * Returns CBX_ERR_LENGTH or the ID (>= 0). */
int cbx_report_peek_id(const uint8_t* report, size_t length);

/* Checks length, report ID, version and CRC of a received report (in that order, so that an
 * incompatible peer is reported as CBX_ERR_VERSION, not as a CRC error). */
cbx_status cbx_report_check(const uint8_t* report, size_t length, uint8_t expected_id);

/* Writes id, header and (after the body is in place) the CRC. Used by every encoder. */
void cbx_report_begin(uint8_t report[CBX_REPORT_SIZE], uint8_t id, const cbx_header* header);
void cbx_report_finish(uint8_t report[CBX_REPORT_SIZE]);
void cbx_report_read_header(const uint8_t report[CBX_REPORT_SIZE], cbx_header* header);

#ifdef __cplusplus
}
#endif
#endif

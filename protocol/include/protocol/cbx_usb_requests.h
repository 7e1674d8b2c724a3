#ifndef CBX_USB_REQUESTS_H
#define CBX_USB_REQUESTS_H
/* Endpoint-0 requests the host sends: HID 1.11 GET_REPORT / SET_REPORT for feature reports, and
 * DFU 1.1 with ST's DfuSe extensions (UM0424, AN3156) for the STM32 ROM bootloader. Shared by
 * the host's transports and flasher and by the emulator (cathbox-emu). */
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum {
  CBX_USB_HID_GET_TYPE = 0xA1, /* bmRequestType: device-to-host, class, interface */
  CBX_USB_HID_SET_TYPE = 0x21, /* host-to-device, class, interface */
  CBX_USB_HID_GET_REPORT = 0x01,
  CBX_USB_HID_SET_REPORT = 0x09,
  CBX_USB_HID_REPORT_FEATURE = 3 /* high byte of wValue; the low byte is the report ID */
};

enum {
  CBX_DFU_OUT_TYPE = 0x21, /* host-to-device, class, interface */
  CBX_DFU_IN_TYPE = 0xA1,
  CBX_DFU_DETACH = 0,
  CBX_DFU_DNLOAD = 1,
  CBX_DFU_UPLOAD = 2,
  CBX_DFU_GETSTATUS = 3,
  CBX_DFU_CLRSTATUS = 4,
  CBX_DFU_GETSTATE = 5,
  CBX_DFU_ABORT = 6,
  CBX_DFU_STATUS_SIZE = 6 /* bStatus, bwPollTimeout (3), bState, iString */
};

/* DFU 1.1 device states (bState). */
typedef enum {
  CBX_DFU_APP_IDLE = 0,
  CBX_DFU_APP_DETACH = 1,
  CBX_DFU_IDLE = 2,
  CBX_DFU_DNLOAD_SYNC = 3,
  CBX_DFU_DNBUSY = 4,
  CBX_DFU_DNLOAD_IDLE = 5,
  CBX_DFU_MANIFEST_SYNC = 6,
  CBX_DFU_MANIFEST = 7,
  CBX_DFU_MANIFEST_WAIT_RESET = 8,
  CBX_DFU_UPLOAD_IDLE = 9,
  CBX_DFU_ERROR = 10
} cbx_dfu_state;

/* DFU 1.1 bStatus values used by the STM32 ROM bootloader. */
typedef enum {
  CBX_DFU_OK = 0x00,
  CBX_DFU_ERR_TARGET = 0x01,  /* address outside the memory or command not supported */
  CBX_DFU_ERR_WRITE = 0x03,   /* programming failed */
  CBX_DFU_ERR_ERASE = 0x04,
  CBX_DFU_ERR_VERIFY = 0x07,
  CBX_DFU_ERR_ADDRESS = 0x08, /* address not erased / out of range */
  CBX_DFU_ERR_STALLEDPKT = 0x0F
} cbx_dfu_status;

/* DfuSe commands: byte 0 of a DNLOAD to block 0 (block 1 is unused; data blocks start at 2,
 * at address pointer + (block - 2) * transfer size). */
enum {
  CBX_DFUSE_GET_COMMANDS = 0x00,
  CBX_DFUSE_SET_ADDRESS = 0x21,
  CBX_DFUSE_ERASE = 0x41,
  CBX_DFUSE_READ_UNPROTECT = 0x92,
  CBX_DFUSE_TRANSFER_SIZE = 2048 /* wTransferSize of the STM32F4 ROM bootloader */
};

#ifdef __cplusplus
}
#endif
#endif

#ifndef CBX_EMU_FRAME_H
#define CBX_EMU_FRAME_H
/* Emulator socket transport (cathbox-emu <-> host, Unix-domain SOCK_SEQPACKET): every datagram
 * is a 4-byte frame header followed by exactly what USB would carry. Interrupt datagrams hold
 * one 64-byte report; control datagrams hold an 8-byte USB SETUP packet and its data stage, so
 * HID feature reports (GET_REPORT / SET_REPORT) and DfuSe requests travel as on endpoint 0.
 * Layout and rules: protocol/README.md, "Emulator socket transport". */
#include "protocol/cbx_protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CBX_EMU_FRAME_HEADER 4u        /* kind, status, tag (u16 LE) */
#define CBX_EMU_SETUP_SIZE 8u          /* USB SETUP packet */
#define CBX_EMU_CONTROL_DATA_MAX 4096u /* largest data stage carried */
#define CBX_EMU_FRAME_MAX (CBX_EMU_FRAME_HEADER + CBX_EMU_SETUP_SIZE + CBX_EMU_CONTROL_DATA_MAX)
#define CBX_EMU_HELLO_SIZE 4u          /* HELLO payload: u16 vid, u16 pid (little-endian) */
#define CBX_EMU_HELLO_FRAME (CBX_EMU_FRAME_HEADER + CBX_EMU_HELLO_SIZE)

typedef enum {
  CBX_EMU_HELLO = 0x01,        /* emu -> host on connect: u16 vid, u16 pid of what is attached */
  CBX_EMU_IN = 0x02,           /* emu -> host: one interrupt IN report (64 bytes) */
  CBX_EMU_OUT = 0x03,          /* host -> emu: one interrupt OUT report (64 bytes) */
  CBX_EMU_CONTROL = 0x04,      /* host -> emu: SETUP (8) + OUT data stage (wLength bytes, or none) */
  CBX_EMU_CONTROL_REPLY = 0x05 /* emu -> host: status + IN data stage (<= wLength bytes) */
} cbx_emu_kind;

typedef enum {
  CBX_EMU_STATUS_OK = 0,    /* the control transfer completed */
  CBX_EMU_STATUS_STALL = 1  /* the device stalled endpoint 0 (request refused) */
} cbx_emu_status;

/* USB SETUP packet fields. */
typedef struct {
  uint8_t request_type; /* bmRequestType: bit 7 = device-to-host */
  uint8_t request;      /* bRequest */
  uint16_t value;       /* wValue */
  uint16_t index;       /* wIndex */
  uint16_t length;      /* wLength */
} cbx_usb_setup;

/* A decoded frame; data points into the caller's buffer (no copy). */
typedef struct {
  uint8_t kind;   /* cbx_emu_kind */
  uint8_t status; /* cbx_emu_status (replies), 0 otherwise */
  uint16_t tag;   /* request tag, echoed by the reply; 0 for interrupt frames */
  cbx_usb_setup setup;      /* CBX_EMU_CONTROL only */
  const uint8_t* data;      /* report, HELLO body, or data stage */
  size_t data_length;
} cbx_emu_frame;

/* The default socket path: $CATHBOX_EMU_SOCKET if set, else $XDG_RUNTIME_DIR/cathbox-emu.sock
 * if XDG_RUNTIME_DIR is set, else /tmp/cathbox-emu.sock. Writes a NUL-terminated path;
 * returns CBX_ERR_LENGTH when it does not fit. */
cbx_status cbx_emu_default_socket_path(char* out, size_t capacity);

/* Writes a frame into out (capacity bytes); returns its length, or a negative cbx_status
 * (CBX_ERR_LENGTH when out is too small or the data has the wrong size for the kind). */
int cbx_emu_frame_encode(const cbx_emu_frame* frame, uint8_t* out, size_t capacity);
/* Parses one datagram. CBX_ERR_LENGTH: shorter than the header or the payload has the wrong
 * size for its kind; CBX_ERR_RANGE: unknown kind or status. frame is written only on success. */
cbx_status cbx_emu_frame_decode(const uint8_t* in, size_t length, cbx_emu_frame* frame);

/* The HELLO the emulator sends first on every connection: which USB device is attached. */
typedef struct {
  uint16_t vid;
  uint16_t pid;
} cbx_emu_hello;

/* Writes the whole HELLO datagram (header + payload) into out; returns its length
 * (CBX_EMU_HELLO_FRAME) or CBX_ERR_LENGTH when out is too small. */
int cbx_emu_hello_encode(const cbx_emu_hello* hello, uint8_t* out, size_t capacity);
/* Reads the HELLO body of a decoded frame. CBX_ERR_RANGE: the frame is not a HELLO;
 * CBX_ERR_LENGTH: its payload is not CBX_EMU_HELLO_SIZE bytes. hello is written only on success. */
cbx_status cbx_emu_hello_decode(const cbx_emu_frame* frame, cbx_emu_hello* hello);

#ifdef __cplusplus
}
#endif
#endif

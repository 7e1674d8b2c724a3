#include "protocol/cbx_hid_descriptor.h"

/* Short items: (tag<<4 | type<<2 | size-code), then 0, 1, 2 or 4 data bytes, little-endian. */
#define CBX_PAYLOAD_BYTES 0x3F /* 63 */
#define CBX_FEATURE(id) 0x85, (id), 0x09, (id), 0xB1, 0x02 /* Report ID, Usage, Feature(Data,Var,Abs) */

const uint8_t cbx_hid_report_descriptor[] = {
    0x06, 0x00, 0xFF,        /* Usage Page (Vendor Defined 0xFF00) */
    0x09, 0x01,              /* Usage (0x01) */
    0xA1, 0x01,              /* Collection (Application) */
    0x15, 0x00,              /*   Logical Minimum (0) */
    0x26, 0xFF, 0x00,        /*   Logical Maximum (255) */
    0x75, 0x08,              /*   Report Size (8) */
    0x95, CBX_PAYLOAD_BYTES, /*   Report Count (63) */
    0x85, 0x01,              /*   Report ID (0x01: state) */
    0x09, 0x01,              /*   Usage (0x01) */
    0x81, 0x02,              /*   Input (Data, Var, Abs) */
    0x85, 0x02,              /*   Report ID (0x02: command) */
    0x09, 0x02,              /*   Usage (0x02) */
    0x91, 0x02,              /*   Output (Data, Var, Abs) */
    CBX_FEATURE(0x10),       /*   device info */
    CBX_FEATURE(0x11),       /*   calibration */
    CBX_FEATURE(0x12),       /*   limits */
    CBX_FEATURE(0x13),       /*   reset counters */
    CBX_FEATURE(0x14),       /*   enter bootloader */
    CBX_FEATURE(0x15),       /*   self-test */
    0xC0                     /* End Collection */
};

const size_t cbx_hid_report_descriptor_size = sizeof cbx_hid_report_descriptor;

#ifndef CBX_HID_DESCRIPTOR_H
#define CBX_HID_DESCRIPTOR_H
/* The HID report descriptor of the box (vendor-defined usage page 0xFF00). Every report has a
 * report ID and a 63-byte payload; see protocol/README.md for the byte-by-byte listing. */
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

extern const uint8_t cbx_hid_report_descriptor[];
extern const size_t cbx_hid_report_descriptor_size;

#ifdef __cplusplus
}
#endif
#endif

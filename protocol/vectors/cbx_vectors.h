#ifndef CBX_VECTORS_H
#define CBX_VECTORS_H
/* Golden vectors of protocol v1, shared by the protocol, firmware, emulator and host tests.
 * Good vectors (expect == CBX_OK) decode to `value` and re-encode to `bytes` exactly; bad ones
 * must be rejected by the decoder named in `kind` with status `expect`. */
#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_image_info.h"
#include "protocol/cbx_state_report.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  const char* name;
  const char* kind; /* state, command, device_info, calibration, limits, reset_counters,
                       enter_bootloader, selftest */
  cbx_status expect;
  size_t length;    /* bytes that are part of the vector (64 except length errors) */
  uint8_t bytes[CBX_REPORT_SIZE];
  union {
    cbx_state_report state;
    cbx_command_report command;
    cbx_device_info device_info;
    cbx_calibration calibration;
    cbx_limits limits;
    cbx_reset_counters reset_counters;
    cbx_enter_bootloader enter_bootloader;
    cbx_selftest selftest;
  } value;
} cbx_vector;

extern const cbx_vector cbx_vectors[];
extern const size_t cbx_vector_count;

/* Firmware image info blocks: good ones (expect == CBX_OK) decode to `value` and encode to
 * `bytes`; bad ones are refused by cbx_image_info_decode with `expect`. */
typedef struct {
  const char* name;
  cbx_status expect;
  uint8_t bytes[CBX_IMAGE_INFO_SIZE];
  cbx_image_info value;
} cbx_image_info_vector;

extern const cbx_image_info_vector cbx_image_info_vectors[];
extern const size_t cbx_image_info_vector_count;

/* Decodes `bytes` with the decoder for `kind` into `out` (a union member of the right kind). */
cbx_status cbx_vector_decode(const cbx_vector* vector, void* out);
/* Encodes `value` with the encoder for `kind`. */
cbx_status cbx_vector_encode(const cbx_vector* vector, uint8_t out[CBX_REPORT_SIZE]);

#ifdef __cplusplus
}
#endif
#endif

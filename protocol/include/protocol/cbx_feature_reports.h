#ifndef CBX_FEATURE_REPORTS_H
#define CBX_FEATURE_REPORTS_H
/* Feature reports (control endpoint): everything that is not the 1 kHz stream.
 * Each is 64 bytes (report ID + 63-byte payload) with the common header and CRC. */
#include "protocol/cbx_protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CBX_TEXT_FIELD 16u          /* serial and board: ASCII 0x20..0x7E, NUL-padded */
#define CBX_BUILD_FIELD 8u          /* build identifier: ASCII 0x20..0x7E, NUL-padded */
#define CBX_CURVE_POINTS 4u
#define CBX_PERMILLE_MAX 1000u
#define CBX_BOOTLOADER_MAGIC 0xB00710ADu

typedef enum { CBX_ACTUATOR_NONE = 0, CBX_ACTUATOR_BRAKE = 1, CBX_ACTUATOR_MOTOR = 2 } cbx_actuator;

/* 0x10 device info (get). */
typedef struct {
  cbx_header header;
  uint8_t fw_major, fw_minor, fw_patch;
  uint8_t protocol_minor;
  char serial[CBX_TEXT_FIELD + 1]; /* NUL-terminated after decode */
  char board[CBX_TEXT_FIELD + 1];
  uint8_t insertion_actuator;      /* cbx_actuator */
  uint8_t rotation_actuator;
  uint32_t insertion_encoder_cpr;  /* encoder counts per encoder revolution (x4 decoding) */
  uint32_t rotation_encoder_cpr;
  char build[CBX_BUILD_FIELD + 1]; /* build identifier of the running image (protocol minor 1),
                                      e.g. the short commit; NUL-terminated after decode */
} cbx_device_info;

/* One point of an output curve: requested |output| -> actuator drive, both in per mille of
 * full scale. The curve runs through (0,0) and the points; beyond the last point it holds. */
typedef struct {
  uint16_t in_permille;  /* strictly increasing along the curve, <= 1000 */
  uint16_t out_permille; /* non-decreasing along the curve, <= 1000 */
} cbx_curve_point;

/* 0x11 calibration (get / set). Zero counts mean "not calibrated". */
typedef struct {
  cbx_header header;
  uint32_t insertion_counts_per_m;
  uint32_t rotation_counts_per_rev;
  uint32_t insertion_full_scale_mN;  /* force at 100 % drive */
  uint32_t rotation_full_scale_uNm;  /* torque at 100 % drive */
  cbx_curve_point insertion_curve[CBX_CURVE_POINTS];
  cbx_curve_point rotation_curve[CBX_CURVE_POINTS];
} cbx_calibration;

/* 0x12 limits (get / set): enforced by the firmware whatever the host commands. */
typedef struct {
  cbx_header header;
  uint32_t max_force_mN;             /* 1..50000 */
  uint32_t max_torque_uNm;           /* 1..1000000 */
  uint16_t watchdog_timeout_ms;      /* 5..1000 (default 50) */
  uint16_t insertion_max_current_mA; /* 1..5000 */
  uint16_t rotation_max_current_mA;  /* 1..5000 */
  uint16_t force_slew_mN_per_ms;     /* >= 1 */
  uint16_t torque_slew_uNm_per_ms;   /* >= 1 */
} cbx_limits;

/* 0x13 reset counters (set). */
enum {
  CBX_RESET_INSERTION_COUNT = 1u << 0,
  CBX_RESET_ROTATION_COUNT = 1u << 1,
  CBX_RESET_ERROR_COUNTERS = 1u << 2,
  CBX_RESET_ALL = 0x07u
};
typedef struct {
  cbx_header header;
  uint8_t mask; /* CBX_RESET_*, at least one bit */
} cbx_reset_counters;

/* 0x14 enter bootloader (set): the box detaches and starts the ROM DFU bootloader. */
typedef struct {
  cbx_header header;
  uint32_t magic; /* must be CBX_BOOTLOADER_MAGIC */
} cbx_enter_bootloader;

/* 0x15 self-test: set with state = RUNNING starts it; get returns the result. */
typedef enum {
  CBX_SELFTEST_NEVER_RUN = 0,
  CBX_SELFTEST_RUNNING = 1,
  CBX_SELFTEST_PASSED = 2,
  CBX_SELFTEST_FAILED = 3
} cbx_selftest_state;
enum {
  CBX_CHECK_INSERTION_ENCODER = 1u << 0,
  CBX_CHECK_ROTATION_ENCODER = 1u << 1,
  CBX_CHECK_INSERTION_ACTUATOR = 1u << 2,
  CBX_CHECK_ROTATION_ACTUATOR = 1u << 3,
  CBX_CHECK_ESTOP = 1u << 4,
  CBX_CHECK_CALIBRATION = 1u << 5,
  CBX_CHECK_ALL = 0x3Fu
};
typedef struct {
  cbx_header header;
  uint8_t state;                /* cbx_selftest_state */
  uint16_t failed_checks;       /* CBX_CHECK_* that failed */
  int16_t insertion_current_mA; /* measured at the test drive level */
  int16_t rotation_current_mA;
  uint16_t supply_mV;
} cbx_selftest;

cbx_status cbx_device_info_encode(const cbx_device_info* v, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_device_info_decode(const uint8_t* in, size_t length, cbx_device_info* v);
cbx_status cbx_calibration_encode(const cbx_calibration* v, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_calibration_decode(const uint8_t* in, size_t length, cbx_calibration* v);
cbx_status cbx_limits_encode(const cbx_limits* v, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_limits_decode(const uint8_t* in, size_t length, cbx_limits* v);
cbx_status cbx_reset_counters_encode(const cbx_reset_counters* v, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_reset_counters_decode(const uint8_t* in, size_t length, cbx_reset_counters* v);
cbx_status cbx_enter_bootloader_encode(const cbx_enter_bootloader* v, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_enter_bootloader_decode(const uint8_t* in, size_t length, cbx_enter_bootloader* v);
cbx_status cbx_selftest_encode(const cbx_selftest* v, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_selftest_decode(const uint8_t* in, size_t length, cbx_selftest* v);

/* Maps a requested output (per mille of full scale, 0..1000) through a curve. */
uint16_t cbx_curve_apply(const cbx_curve_point curve[CBX_CURVE_POINTS], uint16_t in_permille);

#ifdef __cplusplus
}
#endif
#endif

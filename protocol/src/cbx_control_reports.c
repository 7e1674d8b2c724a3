/* Limits, reset counters, enter bootloader and self-test feature reports. */
#include "protocol/cbx_bytes.h"
#include "cbx_codec.h"
#include "protocol/cbx_feature_reports.h"

static cbx_status limits_valid(const void* value) {
  const cbx_limits* v = value;
  if (v->max_force_mN < 1u || v->max_force_mN > 50000u) return CBX_ERR_RANGE;
  if (v->max_torque_uNm < 1u || v->max_torque_uNm > 1000000u) return CBX_ERR_RANGE;
  if (v->watchdog_timeout_ms < 5u || v->watchdog_timeout_ms > 1000u) return CBX_ERR_RANGE;
  if (v->insertion_max_current_mA < 1u || v->insertion_max_current_mA > 5000u) return CBX_ERR_RANGE;
  if (v->rotation_max_current_mA < 1u || v->rotation_max_current_mA > 5000u) return CBX_ERR_RANGE;
  if (v->force_slew_mN_per_ms < 1u || v->torque_slew_uNm_per_ms < 1u) return CBX_ERR_RANGE;
  return CBX_OK;
}

static void limits_put(uint8_t* out, const void* value) {
  const cbx_limits* v = value;
  cbx_put_u32(out + 8, v->max_force_mN);
  cbx_put_u32(out + 12, v->max_torque_uNm);
  cbx_put_u16(out + 16, v->watchdog_timeout_ms);
  cbx_put_u16(out + 18, v->insertion_max_current_mA);
  cbx_put_u16(out + 20, v->rotation_max_current_mA);
  cbx_put_u16(out + 22, v->force_slew_mN_per_ms);
  cbx_put_u16(out + 24, v->torque_slew_uNm_per_ms);
}

static void limits_get(const uint8_t* in, void* value) {
  cbx_limits* v = value;
  v->max_force_mN = cbx_get_u32(in + 8);
  v->max_torque_uNm = cbx_get_u32(in + 12);
  v->watchdog_timeout_ms = cbx_get_u16(in + 16);
  v->insertion_max_current_mA = cbx_get_u16(in + 18);
  v->rotation_max_current_mA = cbx_get_u16(in + 20);
  v->force_slew_mN_per_ms = cbx_get_u16(in + 22);
  v->torque_slew_uNm_per_ms = cbx_get_u16(in + 24);
}

static cbx_status reset_valid(const void* value) {
  const cbx_reset_counters* v = value;
  return (v->mask == 0u || (v->mask & ~CBX_RESET_ALL) != 0u) ? CBX_ERR_RANGE : CBX_OK;
}
static void reset_put(uint8_t* out, const void* value) {
  cbx_put_u8(out + 8, ((const cbx_reset_counters*)value)->mask);
}
static void reset_get(const uint8_t* in, void* value) {
  ((cbx_reset_counters*)value)->mask = cbx_get_u8(in + 8);
}

static cbx_status boot_valid(const void* value) {
  return ((const cbx_enter_bootloader*)value)->magic == CBX_BOOTLOADER_MAGIC ? CBX_OK : CBX_ERR_RANGE;
}
static void boot_put(uint8_t* out, const void* value) {
  cbx_put_u32(out + 8, ((const cbx_enter_bootloader*)value)->magic);
}
static void boot_get(const uint8_t* in, void* value) {
  ((cbx_enter_bootloader*)value)->magic = cbx_get_u32(in + 8);
}

static cbx_status selftest_valid(const void* value) {
  const cbx_selftest* v = value;
  if (v->state > CBX_SELFTEST_FAILED) return CBX_ERR_RANGE;
  if ((v->failed_checks & ~CBX_CHECK_ALL) != 0u) return CBX_ERR_RANGE;
  if (v->state != CBX_SELFTEST_FAILED && v->failed_checks != 0u) return CBX_ERR_RANGE;
  return CBX_OK;
}
static void selftest_put(uint8_t* out, const void* value) {
  const cbx_selftest* v = value;
  cbx_put_u8(out + 8, v->state);
  cbx_put_u16(out + 10, v->failed_checks);
  cbx_put_i16(out + 12, v->insertion_current_mA);
  cbx_put_i16(out + 14, v->rotation_current_mA);
  cbx_put_u16(out + 16, v->supply_mV);
}
static void selftest_get(const uint8_t* in, void* value) {
  cbx_selftest* v = value;
  v->state = cbx_get_u8(in + 8);
  v->failed_checks = cbx_get_u16(in + 10);
  v->insertion_current_mA = cbx_get_i16(in + 12);
  v->rotation_current_mA = cbx_get_i16(in + 14);
  v->supply_mV = cbx_get_u16(in + 16);
}

static const cbx_codec kLimits = {CBX_ID_LIMITS, sizeof(cbx_limits), limits_valid, limits_put,
                                  limits_get};
static const cbx_codec kReset = {CBX_ID_RESET_COUNTERS, sizeof(cbx_reset_counters), reset_valid,
                                 reset_put, reset_get};
static const cbx_codec kBoot = {CBX_ID_ENTER_BOOTLOADER, sizeof(cbx_enter_bootloader), boot_valid,
                                boot_put, boot_get};
static const cbx_codec kSelftest = {CBX_ID_SELFTEST, sizeof(cbx_selftest), selftest_valid,
                                    selftest_put, selftest_get};

cbx_status cbx_limits_encode(const cbx_limits* v, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kLimits, v, out);
}
cbx_status cbx_limits_decode(const uint8_t* in, size_t length, cbx_limits* v) {
  return cbx_codec_decode(&kLimits, in, length, v);
}
cbx_status cbx_reset_counters_encode(const cbx_reset_counters* v, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kReset, v, out);
}
cbx_status cbx_reset_counters_decode(const uint8_t* in, size_t length, cbx_reset_counters* v) {
  return cbx_codec_decode(&kReset, in, length, v);
}
cbx_status cbx_enter_bootloader_encode(const cbx_enter_bootloader* v, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kBoot, v, out);
}
cbx_status cbx_enter_bootloader_decode(const uint8_t* in, size_t length, cbx_enter_bootloader* v) {
  return cbx_codec_decode(&kBoot, in, length, v);
}
cbx_status cbx_selftest_encode(const cbx_selftest* v, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kSelftest, v, out);
}
cbx_status cbx_selftest_decode(const uint8_t* in, size_t length, cbx_selftest* v) {
  return cbx_codec_decode(&kSelftest, in, length, v);
}

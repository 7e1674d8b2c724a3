#include "protocol/cbx_bytes.h"
#include "cbx_codec.h"
#include "protocol/cbx_feature_reports.h"

static int curve_valid(const cbx_curve_point* curve) {
  uint16_t prev_in = 0, prev_out = 0;
  for (size_t i = 0; i < CBX_CURVE_POINTS; ++i) {
    const cbx_curve_point p = curve[i];
    if (p.in_permille > CBX_PERMILLE_MAX || p.out_permille > CBX_PERMILLE_MAX) return 0;
    if (i > 0 && p.in_permille <= prev_in) return 0;
    if (p.out_permille < prev_out) return 0;
    prev_in = p.in_permille;
    prev_out = p.out_permille;
  }
  return 1;
}

uint16_t cbx_curve_apply(const cbx_curve_point curve[CBX_CURVE_POINTS], uint16_t in_permille) {
  uint32_t x0 = 0, y0 = 0;
  for (size_t i = 0; i < CBX_CURVE_POINTS; ++i) {
    const uint32_t x1 = curve[i].in_permille, y1 = curve[i].out_permille;
    if (in_permille <= x1) {
      if (x1 == x0) return (uint16_t)y1;
      return (uint16_t)(y0 + (y1 - y0) * (in_permille - x0) / (x1 - x0));
    }
    x0 = x1;
    y0 = y1;
  }
  return (uint16_t)y0;
}

static cbx_status calibration_valid(const void* value) {
  const cbx_calibration* v = value;
  if (!curve_valid(v->insertion_curve) || !curve_valid(v->rotation_curve)) return CBX_ERR_RANGE;
  return CBX_OK;
}

static void put_curve(uint8_t* p, const cbx_curve_point* curve) {
  for (size_t i = 0; i < CBX_CURVE_POINTS; ++i) {
    cbx_put_u16(p + 4 * i, curve[i].in_permille);
    cbx_put_u16(p + 4 * i + 2, curve[i].out_permille);
  }
}

static void get_curve(const uint8_t* p, cbx_curve_point* curve) {
  for (size_t i = 0; i < CBX_CURVE_POINTS; ++i) {
    curve[i].in_permille = cbx_get_u16(p + 4 * i);
    curve[i].out_permille = cbx_get_u16(p + 4 * i + 2);
  }
}

static void calibration_put(uint8_t* out, const void* value) {
  const cbx_calibration* v = value;
  cbx_put_u32(out + 8, v->insertion_counts_per_m);
  cbx_put_u32(out + 12, v->rotation_counts_per_rev);
  cbx_put_u32(out + 16, v->insertion_full_scale_mN);
  cbx_put_u32(out + 20, v->rotation_full_scale_uNm);
  put_curve(out + 24, v->insertion_curve);
  put_curve(out + 40, v->rotation_curve);
}

static void calibration_get(const uint8_t* in, void* value) {
  cbx_calibration* v = value;
  v->insertion_counts_per_m = cbx_get_u32(in + 8);
  v->rotation_counts_per_rev = cbx_get_u32(in + 12);
  v->insertion_full_scale_mN = cbx_get_u32(in + 16);
  v->rotation_full_scale_uNm = cbx_get_u32(in + 20);
  get_curve(in + 24, v->insertion_curve);
  get_curve(in + 40, v->rotation_curve);
}

static const cbx_codec kCalibrationCodec = {CBX_ID_CALIBRATION, sizeof(cbx_calibration),
                                            calibration_valid, calibration_put, calibration_get};

cbx_status cbx_calibration_encode(const cbx_calibration* v, uint8_t out[CBX_REPORT_SIZE]) {
  return cbx_codec_encode(&kCalibrationCodec, v, out);
}
cbx_status cbx_calibration_decode(const uint8_t* in, size_t length, cbx_calibration* v) {
  return cbx_codec_decode(&kCalibrationCodec, in, length, v);
}

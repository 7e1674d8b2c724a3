#include "firmware/cbx_render.h"

#include "protocol/cbx_state_report.h"

void cbx_axis_scale_set(cbx_axis_scale* s, uint32_t counts_per_unit, uint64_t units_per_unit,
                        uint32_t full_scale, const cbx_curve_point* curve, uint32_t max_out,
                        uint32_t slew_per_ms) {
  s->valid = (uint8_t)(counts_per_unit != 0u && full_scale != 0u);
  s->pos_scale_q16 = counts_per_unit ? (int64_t)((units_per_unit << 16) / counts_per_unit) : 0;
  s->pos_count_limit =
      s->pos_scale_q16 > 0 ? (int32_t)((INT64_MAX >> 1) / s->pos_scale_q16 > INT32_MAX
                                           ? INT32_MAX
                                           : (INT64_MAX >> 1) / s->pos_scale_q16)
                           : INT32_MAX;
  s->permille_scale_q16 = full_scale ? (uint32_t)((1000ull << 16) / full_scale) : 0u;
  s->max_out = max_out > (uint32_t)INT32_MAX ? INT32_MAX : (int32_t)max_out;
  s->slew_per_ms = slew_per_ms > (uint32_t)INT32_MAX ? INT32_MAX : (int32_t)slew_per_ms;
  s->curve = curve;
}

static int32_t saturate(int64_t v) {
  if (v > INT32_MAX) return INT32_MAX;
  if (v < INT32_MIN) return INT32_MIN;
  return (int32_t)v;
}

int32_t cbx_axis_scale_position(const cbx_axis_scale* s, int32_t counts) {
  if (counts > s->pos_count_limit) return INT32_MAX;
  if (counts < -s->pos_count_limit) return INT32_MIN;
  const int64_t q = (int64_t)counts * s->pos_scale_q16;
  /* Round half away from zero so that +x and -x map symmetrically. */
  return saturate(q >= 0 ? (q + 32768) >> 16 : -((-q + 32768) >> 16));
}

int32_t cbx_render_target(const cbx_axis_scale* s, uint8_t mode, int32_t law_out, int32_t vel) {
  int32_t out = law_out;
  if (out > s->max_out) out = s->max_out;
  if (out < -s->max_out) out = -s->max_out;
  if (mode == CBX_MODE_BRAKE && ((vel > 0 && out > 0) || (vel < 0 && out < 0))) out = 0;
  if (mode == CBX_MODE_OFF) out = 0;
  return out;
}

int32_t cbx_render_slew(int32_t current, int32_t target, int32_t step) {
  const int64_t d = (int64_t)target - current;
  if (d > step) return (int32_t)((int64_t)current + step);
  if (d < -(int64_t)step) return (int32_t)((int64_t)current - step);
  return target;
}

int16_t cbx_render_drive(const cbx_axis_scale* s, uint8_t mode, int32_t out) {
  if (!s->valid || out == 0 || mode == CBX_MODE_OFF) return 0;
  const uint32_t magnitude = out > 0 ? (uint32_t)out : (uint32_t)(-(int64_t)out);
  uint64_t permille = ((uint64_t)magnitude * s->permille_scale_q16 + 32768u) >> 16;
  if (permille > CBX_PERMILLE_MAX) permille = CBX_PERMILLE_MAX;
  const int16_t drive = (int16_t)cbx_curve_apply(s->curve, (uint16_t)permille);
  if (mode == CBX_MODE_BRAKE) return drive;
  return out > 0 ? drive : (int16_t)-drive;
}

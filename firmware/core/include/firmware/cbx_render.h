#ifndef CBX_RENDER_H
#define CBX_RENDER_H
/* Force rendering for one axis, once per control tick: encoder counts -> physical position
 * and velocity (calibration) -> the command's local force law -> limit clamp -> brake
 * passivity -> slew limit -> output curve -> actuator drive in per mille. */
#include <stdint.h>

#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Per-axis scale factors, derived from the calibration and limits when they change, so the
 * tick has no divisions. */
typedef struct {
  int64_t pos_scale_q16;       /* (um or urad) per count, Q16 */
  int32_t pos_count_limit;     /* |count| beyond which count * scale would overflow */
  uint32_t permille_scale_q16; /* per mille of full scale per mN (or uNm), Q16 */
  int32_t max_out;             /* limit clamp, mN or uNm */
  int32_t slew_per_ms;         /* mN (uNm) per ms */
  const cbx_curve_point* curve;
  uint8_t valid;               /* calibrated: counts per unit and full scale both nonzero */
} cbx_axis_scale;

typedef struct {
  int32_t pos;      /* um or urad */
  int32_t vel;      /* um/s or urad/s */
  int32_t out;      /* output after clamps and slew: mN or uNm (the readback) */
  int16_t drive;    /* actuator drive, per mille, signed */
} cbx_axis_output;

/* Fills `s` from calibration values; `units_per_rev_or_m` is 1e6 um per m or 2*pi*1e6 urad per
 * revolution. */
void cbx_axis_scale_set(cbx_axis_scale* s, uint32_t counts_per_unit, uint64_t units_per_unit,
                        uint32_t full_scale, const cbx_curve_point* curve, uint32_t max_out,
                        uint32_t slew_per_ms);
/* Counts (or counts/s) to um or urad (or per second), saturating. */
int32_t cbx_axis_scale_position(const cbx_axis_scale* s, int32_t counts);

/* Output after the limit clamp and, in brake mode, passivity (a brake can only oppose the
 * motion; at rest it may hold either way). */
int32_t cbx_render_target(const cbx_axis_scale* s, uint8_t mode, int32_t law_out, int32_t vel);
/* Moves `current` toward `target` by at most `step` (>= 0). */
int32_t cbx_render_slew(int32_t current, int32_t target, int32_t step);
/* Output (mN or uNm, signed) to drive per mille through the calibration curve. In brake
 * mode the drive is the magnitude (>= 0). */
int16_t cbx_render_drive(const cbx_axis_scale* s, uint8_t mode, int32_t out);

#ifdef __cplusplus
}
#endif
#endif

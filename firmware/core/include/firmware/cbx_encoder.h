#ifndef CBX_ENCODER_H
#define CBX_ENCODER_H
/* One quadrature encoder: position from a hardware counter (any width, extended to 32 bits)
 * or from raw A/B samples (x4 decoding, illegal transitions counted), and a velocity estimate
 * that measures over at least 1 ms at speed and over the edge period at low speed. */
#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  CBX_ENCODER_COUNTER = 0, /* the port's timer counts; the core reads cbx_hal_encoder_counter() */
  CBX_ENCODER_EDGES = 1    /* the port (or the emulator) feeds A/B samples: cbx_core_encoder_edge() */
} cbx_encoder_source;

#define CBX_ENCODER_WINDOW_US 1000u    /* shortest velocity measurement window */
#define CBX_ENCODER_STOP_US 250000u    /* no count change for this long: velocity 0 */

typedef struct {
  uint8_t source;        /* cbx_encoder_source */
  uint8_t counter_bits;  /* width of the hardware counter, 2..32 (counter source) */
  uint8_t ab;            /* last A/B sample: bit 0 = A, bit 1 = B (edge source) */
  int8_t direction;      /* last step direction, -1, 0, +1 */
  uint32_t last_raw;     /* last hardware counter reading (counter source) */
  int32_t count;         /* position in counts, extended to 32 bits (wraps as int32) */
  uint32_t errors;       /* illegal transitions (both lines changed at once), saturating */
  int32_t vel_cps;       /* velocity estimate, counts per second */
  int32_t ref_count;     /* velocity window start */
  uint32_t ref_time_us;
  int32_t seen_count;    /* count at the previous update */
  uint32_t change_time_us; /* time of the last update that saw the count change */
} cbx_encoder;

/* Starts at count 0; for a counter source, `raw` is the counter's current value. */
void cbx_encoder_init(cbx_encoder* e, cbx_encoder_source source, uint8_t counter_bits,
                      uint32_t raw, uint32_t now_us);
/* One A/B sample (edge source). Unchanged lines: nothing; one line changed: one count;
 * both changed (a missed edge or noise): an error, and two counts in the last direction. */
void cbx_encoder_edge(cbx_encoder* e, uint8_t ab);
/* The lines' present A/B state (edge source), taken without counting: for lines that do not
 * rest at 00 when decoding starts. */
void cbx_encoder_rest(cbx_encoder* e, uint8_t ab);
/* Once per control tick: takes the counter reading (ignored for the edge source) and updates
 * the velocity estimate. */
void cbx_encoder_update(cbx_encoder* e, uint32_t raw, uint32_t now_us);
/* Sets the position to 0 without disturbing the velocity estimate. */
void cbx_encoder_zero(cbx_encoder* e);

#ifdef __cplusplus
}
#endif
#endif

#include "firmware/cbx_encoder.h"

/* Gray-code order of the A/B states: 00 -> 01 -> 11 -> 10 -> 00 is one direction (+). */
static const uint8_t gray_index[4] = {0u, 1u, 3u, 2u};

void cbx_encoder_init(cbx_encoder* e, cbx_encoder_source source, uint8_t counter_bits,
                      uint32_t raw, uint32_t now_us) {
  e->source = (uint8_t)source;
  e->counter_bits = (counter_bits < 2u || counter_bits > 32u) ? 32u : counter_bits;
  e->ab = 0u;
  e->direction = 0;
  e->last_raw = raw;
  e->count = 0;
  e->errors = 0u;
  e->vel_cps = 0;
  e->ref_count = 0;
  e->ref_time_us = now_us;
  e->seen_count = 0;
  e->change_time_us = now_us;
}

static void step(cbx_encoder* e, int32_t counts) {
  e->count = (int32_t)((uint32_t)e->count + (uint32_t)counts);
}

void cbx_encoder_edge(cbx_encoder* e, uint8_t ab) {
  ab &= 3u;
  const uint8_t diff = (uint8_t)((gray_index[ab] - gray_index[e->ab]) & 3u);
  e->ab = ab;
  if (diff == 1u) {
    e->direction = 1;
    step(e, 1);
  } else if (diff == 3u) {
    e->direction = -1;
    step(e, -1);
  } else if (diff == 2u) {
    /* Both lines changed: an edge was missed (or noise). The most likely truth is two
     * steps in the direction of travel; unknown direction leaves the count alone. */
    if (e->errors != UINT32_MAX) e->errors++;
    step(e, 2 * (int32_t)e->direction);
  }
}

/* Sign-extends the difference of two readings of a `bits`-wide counter. */
static int32_t counter_delta(uint32_t raw, uint32_t last, uint8_t bits) {
  uint32_t d = raw - last;
  if (bits >= 32u) return (int32_t)d;
  const uint32_t mask = (1u << bits) - 1u;
  const uint32_t sign = 1u << (bits - 1u);
  d &= mask;
  return (d & sign) ? -(int32_t)(mask - d + 1u) : (int32_t)d;
}

void cbx_encoder_update(cbx_encoder* e, uint32_t raw, uint32_t now_us) {
  if (e->source == CBX_ENCODER_COUNTER) {
    const int32_t d = counter_delta(raw, e->last_raw, e->counter_bits);
    e->last_raw = raw;
    if (d != 0) e->direction = d > 0 ? 1 : -1;
    step(e, d);
  }
  const int32_t count = e->count;
  if (count != e->seen_count) {
    /* A change: measure over the window since the reference, once it spans >= 1 ms.
     * At low speed that window is the edge period, at speed it is about 1 ms. */
    const uint32_t dt = now_us - e->ref_time_us;
    if (dt >= CBX_ENCODER_WINDOW_US) {
      const int32_t dc = (int32_t)((uint32_t)count - (uint32_t)e->ref_count);
      if (dt > CBX_ENCODER_STOP_US) {
        /* Starting from rest: one window's worth is all we know. */
        e->vel_cps = dc > 0 ? (int32_t)(1000000u / CBX_ENCODER_STOP_US)
                            : -(int32_t)(1000000u / CBX_ENCODER_STOP_US);
      } else {
        /* 32-bit hardware division whenever the product fits (the common case). */
        e->vel_cps = (dc <= 2147 && dc >= -2147 && dt <= (uint32_t)INT32_MAX)
                         ? dc * 1000000 / (int32_t)dt
                         : (int32_t)(((int64_t)dc * 1000000) / (int64_t)dt);
      }
      e->ref_count = count;
      e->ref_time_us = now_us;
    }
    e->seen_count = count;
    e->change_time_us = now_us;
  } else {
    /* No change: the speed cannot be above one count per elapsed time; decay to that bound
     * and to zero after the stop time. At rest the reference times follow the clock, so
     * that they never age past its wrap (2^32 us) and a restart always reads as one. */
    const uint32_t idle = now_us - e->change_time_us;
    if (idle >= CBX_ENCODER_STOP_US) {
      e->vel_cps = 0;
      e->ref_count = count;
      e->ref_time_us = now_us - CBX_ENCODER_STOP_US - 1u;
      e->change_time_us = now_us - CBX_ENCODER_STOP_US;
    } else if (idle > 0u && e->vel_cps != 0) {
      const int32_t bound = (int32_t)(1000000u / idle);
      if (e->vel_cps > bound) e->vel_cps = bound;
      if (e->vel_cps < -bound) e->vel_cps = -bound;
    }
  }
}

void cbx_encoder_rest(cbx_encoder* e, uint8_t ab) { e->ab = (uint8_t)(ab & 3u); }

void cbx_encoder_zero(cbx_encoder* e) {
  const int32_t offset = e->count;
  e->count = 0;
  e->seen_count = (int32_t)((uint32_t)e->seen_count - (uint32_t)offset);
  e->ref_count = (int32_t)((uint32_t)e->ref_count - (uint32_t)offset);
}

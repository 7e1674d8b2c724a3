/* Quadrature decoding (edges with noise and missed edges, counters with wrap) and the
 * velocity estimate. */
#include "cbx_test.h"
#include "firmware/cbx_encoder.h"

static const uint8_t forward[4] = {0u, 1u, 3u, 2u}; /* A leads B */

static void feed_cycles(cbx_encoder* e, int steps) {
  static int phase = 0;
  for (int i = 0; i < (steps < 0 ? -steps : steps); ++i) {
    phase = (phase + (steps > 0 ? 1 : 3)) & 3;
    cbx_encoder_edge(e, forward[phase]);
  }
}

static void edges_count_both_ways(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_EDGES, 0, 0u, 0u);
  for (int i = 1; i <= 16; ++i) cbx_encoder_edge(&e, forward[i & 3]);
  CBX_CHECK_EQ(e.count, 16);
  for (int i = 15; i >= 0; --i) cbx_encoder_edge(&e, forward[i & 3]);
  CBX_CHECK_EQ(e.count, 0);
  CBX_CHECK_EQ(e.errors, 0);
}

static void edges_bounce_is_not_motion(void) {
  /* Contact bounce on A at one position: 00 -> 01 -> 00 -> 01 -> 00 nets zero, no errors. */
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_EDGES, 0, 0u, 0u);
  for (int i = 0; i < 50; ++i) {
    cbx_encoder_edge(&e, 1u);
    cbx_encoder_edge(&e, 0u);
  }
  CBX_CHECK_EQ(e.count, 0);
  CBX_CHECK_EQ(e.errors, 0);
  /* Repeated identical samples (a sampled input with no edge) change nothing either. */
  for (int i = 0; i < 10; ++i) cbx_encoder_edge(&e, 0u);
  CBX_CHECK_EQ(e.count, 0);
}

static void edges_missed_edge_counted_and_bridged(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_EDGES, 0, 0u, 0u);
  cbx_encoder_edge(&e, 1u); /* +1 */
  cbx_encoder_edge(&e, 3u); /* +2 */
  cbx_encoder_edge(&e, 0u); /* skipped 2: illegal, bridged as +2 in the direction of travel */
  CBX_CHECK_EQ(e.errors, 1);
  CBX_CHECK_EQ(e.count, 4);
  cbx_encoder_edge(&e, 1u);
  CBX_CHECK_EQ(e.count, 5);
  /* Backwards, then a miss: bridged backwards. */
  cbx_encoder_edge(&e, 0u); /* 4 */
  cbx_encoder_edge(&e, 3u); /* illegal from 00 to 11 going backwards: -2 */
  CBX_CHECK_EQ(e.count, 2);
  CBX_CHECK_EQ(e.errors, 2);
}

static void edges_illegal_at_rest_keeps_count(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_EDGES, 0, 0u, 0u);
  cbx_encoder_edge(&e, 3u); /* no direction known yet */
  CBX_CHECK_EQ(e.count, 0);
  CBX_CHECK_EQ(e.errors, 1);
}

static void edges_start_from_the_resting_lines(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_EDGES, 0, 0u, 0u);
  cbx_encoder_rest(&e, 3u); /* lines rest at 11: no count, no error */
  CBX_CHECK_EQ(e.count, 0);
  CBX_CHECK_EQ(e.errors, 0);
  cbx_encoder_edge(&e, 2u); /* 11 -> 10: one count forward */
  CBX_CHECK_EQ(e.count, 1);
  CBX_CHECK_EQ(e.errors, 0);
}

static void edges_noisy_stream_tracks_position(void) {
  /* 400 forward steps with a bounce after every 7th edge and a missed edge every 50th:
   * the count ends where the shaft is and every miss is counted. */
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_EDGES, 0, 0u, 0u);
  int phase = 0, misses = 0;
  for (int i = 1; i <= 400; ++i) {
    phase = (phase + 1) & 3;
    if (i % 50 == 0 && i < 400) {
      misses++;
      continue; /* this edge is never seen */
    }
    cbx_encoder_edge(&e, forward[phase]);
    if (i % 7 == 0) {
      cbx_encoder_edge(&e, forward[(phase + 3) & 3]);
      cbx_encoder_edge(&e, forward[phase]);
    }
  }
  CBX_CHECK_EQ(e.count, 400);
  CBX_CHECK_EQ(e.errors, misses);
}

static void counter_16bit_extends_across_wrap(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_COUNTER, 16, 65530u, 0u);
  cbx_encoder_update(&e, 5u, 100u);
  CBX_CHECK_EQ(e.count, 11);
  cbx_encoder_update(&e, 65000u, 200u);
  CBX_CHECK_EQ(e.count, 11 - 541);
  /* Many wraps forward in steps below half the range: 32-bit position. */
  uint32_t raw = 65000u;
  for (int i = 0; i < 100; ++i) {
    raw = (raw + 30000u) & 0xFFFFu;
    cbx_encoder_update(&e, raw, 300u + (uint32_t)i * 100u);
  }
  CBX_CHECK_EQ(e.count, 11 - 541 + 3000000);
}

static void counter_32bit_wraps_as_int32(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_COUNTER, 32, 0xFFFFFFF0u, 0u);
  cbx_encoder_update(&e, 0x10u, 100u);
  CBX_CHECK_EQ(e.count, 32);
  cbx_encoder_update(&e, 0xFFFFFFF0u, 200u);
  CBX_CHECK_EQ(e.count, 0);
  /* Counter widths other than 16/32 (e.g. a 24-bit counter) extend the same way. */
  cbx_encoder_init(&e, CBX_ENCODER_COUNTER, 24, 0xFFFFFEu, 0u);
  cbx_encoder_update(&e, 0x000002u, 100u);
  CBX_CHECK_EQ(e.count, 4);
}

static void velocity_at_speed(void) {
  /* 20 counts per 100 us tick = 200000 counts/s. */
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_COUNTER, 16, 0u, 0u);
  uint32_t raw = 0u;
  for (uint32_t t = 100u; t <= 20000u; t += 100u) {
    raw = (raw + 20u) & 0xFFFFu;
    cbx_encoder_update(&e, raw, t);
  }
  CBX_CHECK_NEAR(e.vel_cps, 200000, 2000);
  /* 3 counts per tick backwards = -30000 counts/s. */
  for (uint32_t t = 20100u; t <= 40000u; t += 100u) {
    raw = (raw - 3u) & 0xFFFFu;
    cbx_encoder_update(&e, raw, t);
  }
  CBX_CHECK_NEAR(e.vel_cps, -30000, 300);
}

static void velocity_at_low_speed_stays_sane(void) {
  /* One count every 40 ms = 25 counts/s: never above the true rate by much, never noisy
   * spikes of 10000 counts/s (one count in one tick), and zero after the stop time. */
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_COUNTER, 16, 0u, 0u);
  uint32_t raw = 0u;
  int32_t max_seen = 0;
  for (uint32_t t = 100u; t <= 1000000u; t += 100u) {
    if (t % 40000u == 0u) raw++;
    cbx_encoder_update(&e, raw, t);
    if (e.vel_cps > max_seen) max_seen = e.vel_cps;
    if (t > 200000u) CBX_CHECK_RANGE(e.vel_cps, 12, 25);
  }
  CBX_CHECK_RANGE(max_seen, 1, 25);
  CBX_CHECK_NEAR(e.vel_cps, 25, 1);
  /* Stop: the estimate falls as 1/idle time and reaches zero. */
  int32_t previous = e.vel_cps;
  for (uint32_t t = 1000100u; t <= 1400000u; t += 100u) {
    cbx_encoder_update(&e, raw, t);
    CBX_CHECK(e.vel_cps <= previous);
    previous = e.vel_cps;
  }
  CBX_CHECK_EQ(e.vel_cps, 0);
  /* Restart from rest: a small positive figure, not a spike. */
  cbx_encoder_update(&e, raw + 1u, 1400100u);
  CBX_CHECK_RANGE(e.vel_cps, 1, 10);
}

static void velocity_reverses(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_EDGES, 0, 0u, 0u);
  for (uint32_t t = 100u; t <= 10000u; t += 100u) {
    feed_cycles(&e, 1);
    cbx_encoder_update(&e, 0u, t);
  }
  CBX_CHECK_NEAR(e.vel_cps, 10000, 100);
  for (uint32_t t = 10100u; t <= 20000u; t += 100u) {
    feed_cycles(&e, -2);
    cbx_encoder_update(&e, 0u, t);
  }
  CBX_CHECK_NEAR(e.vel_cps, -20000, 200);
  CBX_CHECK_EQ(e.errors, 0);
}

static void zero_keeps_velocity(void) {
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_COUNTER, 16, 0u, 0u);
  uint32_t raw = 0u;
  for (uint32_t t = 100u; t <= 5000u; t += 100u) cbx_encoder_update(&e, raw += 5u, t);
  const int32_t v = e.vel_cps;
  cbx_encoder_zero(&e);
  CBX_CHECK_EQ(e.count, 0);
  for (uint32_t t = 5100u; t <= 7000u; t += 100u) cbx_encoder_update(&e, raw += 5u, t);
  CBX_CHECK_EQ(e.count, 100);
  CBX_CHECK_NEAR(e.vel_cps, v, 500);
}

static void velocity_after_a_rest_longer_than_the_clock_wrap(void) {
  /* The microsecond clock wraps every 2^32 us (71.6 min). A tool at rest for longer than
   * that and then moved by one count is still a start from rest, not one count over the
   * wrapped remainder of the rest. Updates every 100 ms stand in for the ticks. */
  cbx_encoder e;
  cbx_encoder_init(&e, CBX_ENCODER_COUNTER, 16, 0u, 0u);
  uint32_t t = 0u;
  for (uint32_t i = 0; i < 42950u; ++i) { /* 4295 s: just past 2^32 us */
    t += 100000u;
    cbx_encoder_update(&e, 0u, t);
    CBX_CHECK_EQ(e.vel_cps, 0);
  }
  cbx_encoder_update(&e, 1u, t + 50000u); /* (t + 50 ms) mod 2^32 ~ 0.03 s after a wrap */
  CBX_CHECK_RANGE(e.vel_cps, 1, (int32_t)(1000000u / CBX_ENCODER_STOP_US));
}

const cbx_test_case cbx_tests_encoder[] = {
    {"edges_count_both_ways", edges_count_both_ways},
    {"edges_bounce_is_not_motion", edges_bounce_is_not_motion},
    {"edges_missed_edge_counted_and_bridged", edges_missed_edge_counted_and_bridged},
    {"edges_illegal_at_rest_keeps_count", edges_illegal_at_rest_keeps_count},
    {"edges_start_from_the_resting_lines", edges_start_from_the_resting_lines},
    {"edges_noisy_stream_tracks_position", edges_noisy_stream_tracks_position},
    {"counter_16bit_extends_across_wrap", counter_16bit_extends_across_wrap},
    {"counter_32bit_wraps_as_int32", counter_32bit_wraps_as_int32},
    {"velocity_at_speed", velocity_at_speed},
    {"velocity_at_low_speed_stays_sane", velocity_at_low_speed_stays_sane},
    {"velocity_reverses", velocity_reverses},
    {"zero_keeps_velocity", zero_keeps_velocity},
    {"velocity_after_a_rest_longer_than_the_clock_wrap", velocity_after_a_rest_longer_than_the_clock_wrap},
    {0, 0}};

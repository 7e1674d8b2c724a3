#ifndef CBX_CORE_INTERNAL_H
#define CBX_CORE_INTERNAL_H
/* Shared between the core's translation units; not part of the public API. */
#include <stdatomic.h>

#include "firmware/cbx_core.h"

#define CBX_SELFTEST_DRIVE_PERMILLE 200
#define CBX_SELFTEST_PHASE_US 20000u
#define CBX_SELFTEST_MIN_CURRENT_MA 20

/* The per-axis scales for a set of settings (64-bit divisions: computed by whoever publishes
 * the settings, never by the tick). The curves point into `s`. */
void cbx_core_scales(const cbx_settings* s, cbx_axis_scale scale[CBX_AXIS_COUNT]);
/* Self-test step for one tick; returns true while the test owns the actuators. */
bool cbx_selftest_tick(cbx_core* core, uint32_t now_us, bool estop_pressed,
                       const int16_t current_mA[CBX_AXIS_COUNT]);
/* Ends a running self-test as failed with `checks` (a hard cut interrupted it). */
void cbx_selftest_abort(cbx_core* core, uint16_t checks);
/* Starts a self-test (tick context). */
void cbx_selftest_start(cbx_core* core, uint32_t now_us);

/* Keeps the compiler from moving plain loads and stores of the mailboxes and the snapshot
 * across the volatile hand-over fields (slot index, generation, sequence). The contexts run
 * on one core, so ordering by the compiler is all that is needed. */
#define CBX_COMPILER_BARRIER() atomic_signal_fence(memory_order_seq_cst)

/* Copies tick-owned data consistently from another context: retry while a tick ran. */
#define CBX_TICK_CONSISTENT(core, stmt)                     \
  do {                                                      \
    uint32_t cbx_seq_;                                      \
    do {                                                    \
      cbx_seq_ = (core)->snapshot_seq;                      \
      CBX_COMPILER_BARRIER();                               \
      stmt;                                                 \
      CBX_COMPILER_BARRIER();                               \
    } while (cbx_seq_ != (core)->snapshot_seq);             \
  } while (0)

#endif

// The haptic worker's 1 kHz clock (js/train_worker.js), apart from the session so that its logic
// is tested in virtual time (tests/host/wasm/tick_clock_test.mjs): `now()` and `sleep(ms)` are
// given. In the worker they are performance.now() and Atomics.wait on a SharedArrayBuffer, which a
// dedicated worker may block in (timers are clamped to >= 1-4 ms; Atomics.wait is not).
//
// Tick k is due at start + k ms. slice(tick) runs the due ticks, then sleeps to the next
// deadline, until sliceMs have passed; then the worker returns to its event loop (messages, the
// record writer's file calls, frames) and calls slice() again. The sleep ends spinMs before the
// deadline and the last stretch is a tight loop on now(): a woken thread is late by the system's
// wake-up latency, a spinning one is not. Behind by more than maxCatchUp ticks, the overdue
// ticks beyond those are dropped and counted (the native haptic thread's session::HapticPacer
// drops beyond MAX_CATCH_UP = 4); up to maxCatchUp ticks are run back to back, in the session's
// virtual time, so a stall shorter than that costs no simulated time.
import { TickStats } from './tick_stats.js';

export const MAX_CATCH_UP = 4;

export class TickClock {
  constructor({ now, sleep, periodMs = 1, sliceMs = 8, spinMs = 0.2, maxCatchUp = MAX_CATCH_UP }) {
    this.maxCatchUp = maxCatchUp;
    this.now = now;
    this.sleep = sleep;
    this.periodMs = periodMs;
    this.sliceMs = sliceMs;
    this.spinMs = spinMs;
    this.stats = new TickStats();
    this.startAt = 0;
    this.due = 0;  // the next tick's number
    this.after = 'yield';
  }

  begin() {
    this.startAt = this.now();
    this.due = 0;
    this.after = 'yield';
  }

  deadline() { return this.startAt + this.due * this.periodMs; }

  // Runs one slice; tick() runs one session tick and returns false once the run is over.
  // Returns 'over' or 'yield'.
  slice(tick) {
    const sliceEnd = this.now() + this.sliceMs;
    for (;;) {
      let t = this.now();
      while (this.deadline() <= t) {
        const behind = Math.floor((t - this.startAt) / this.periodMs) - this.due + 1;
        if (behind > this.maxCatchUp) {
          this.stats.dropped += behind - this.maxCatchUp;
          this.due += behind - this.maxCatchUp;
        }
        this.stats.start(t, this.deadline(), this.after);
        const more = tick();
        const end = this.now();
        this.stats.ran(end - t);
        ++this.due;
        this.after = 'tick';
        if (!more) return 'over';
        t = end;
        if (t >= sliceEnd) break;  // ticks that run long still leave the event loop its turn
      }
      if (t >= sliceEnd) {
        this.after = 'yield';
        return 'yield';
      }
      const wait = this.deadline() - t - this.spinMs;
      if (wait > 0) this.sleep(wait);
      while (this.now() < this.deadline());  // the last stretch (spinMs at most, unless woken late)
      this.after = 'sleep';
    }
  }
}

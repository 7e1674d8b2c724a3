// The haptic worker's tick timing, measured (js/tick_clock.js fills it): a 10 µs histogram each
// of the interval between consecutive ticks, of each tick's lateness (its start minus its
// deadline) and of each tick's own run time; and what the late ticks (more than LATE_MS after
// their deadline) came after — a sleep the system woke late from, ticks that ran long, or the
// worker's event loop (messages, frames, garbage collection) — so the jitter can be put down to
// its cause (only the first late tick of a stall is put down to a cause; the ones run back to back
// after it are counted as catch_up). Plain numbers: the worker posts report() at the end of the run.
export const BIN_MS = 0.01;
export const BINS = 10000;  // up to 100 ms; longer ones land in the last bin
export const LATE_MS = 0.5;

export class Histogram {
  constructor() {
    this.bins = new Uint32Array(BINS + 1);
    this.count = 0;
    this.max = 0;
  }

  add(ms) {
    this.bins[Math.min(BINS, Math.max(0, Math.floor(ms / BIN_MS)))]++;
    this.count++;
    if (ms > this.max) this.max = ms;
  }

  // The bin's middle that holds the p-th fraction (null when empty).
  percentile(p) {
    if (this.count === 0) return null;
    const want = Math.max(1, Math.ceil(p * this.count));
    let seen = 0;
    for (let i = 0; i <= BINS; ++i) {
      seen += this.bins[i];
      if (seen >= want) return i === BINS ? this.max : (i + 0.5) * BIN_MS;
    }
    return this.max;
  }
}

export class TickStats {
  constructor() {
    this.interval = new Histogram();
    this.lateness = new Histogram();
    this.run = new Histogram();
    this.lastAt = -1;
    this.dropped = 0;
    this.late = { after_sleep: 0, after_ticks: 0, after_yield: 0, catch_up: 0 };
    this.wasLate = false;
    this.worstRecent = 0;  // the worst lateness since takeWorst() (the page's frame pacing)
  }

  // A tick starting at `at` (ms) for its deadline `due` (ms); `after` what the worker did
  // just before: 'sleep', 'tick' or 'yield'.
  start(at, due, after) {
    if (this.lastAt >= 0) this.interval.add(at - this.lastAt);
    this.lastAt = at;
    this.lateness.add(at - due);
    if (at - due > this.worstRecent) this.worstRecent = at - due;
    const late = at - due > LATE_MS;
    if (late && this.wasLate) this.late.catch_up++;
    else if (late) {
      if (after === 'sleep') this.late.after_sleep++;
      else if (after === 'tick') this.late.after_ticks++;
      else this.late.after_yield++;
    }
    this.wasLate = late;
  }

  ran(ms) { this.run.add(ms); }

  // The worst lateness (ms) since the last call, and start afresh.
  takeWorst() {
    const worst = this.worstRecent;
    this.worstRecent = 0;
    return worst;
  }

  report() {
    const r3 = (v) => (v === null ? null : Math.round(v * 1000) / 1000);
    return {
      ticks: this.lateness.count, dropped: this.dropped,
      p50_ms: r3(this.interval.percentile(0.5)), p99_ms: r3(this.interval.percentile(0.99)), max_ms: r3(this.interval.max),
      late_p50_ms: r3(this.lateness.percentile(0.5)), late_p99_ms: r3(this.lateness.percentile(0.99)), late_max_ms: r3(this.lateness.max),
      tick_p50_ms: r3(this.run.percentile(0.5)), tick_p99_ms: r3(this.run.percentile(0.99)),
      late_ticks: { ...this.late },
    };
  }
}

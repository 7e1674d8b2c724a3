// The page's drawing paced by the haptic worker's health: an adaptive frame budget, the way a
// real-time application keeps its control loop first. On a machine with few cores (and a software
// GL, whose raster threads take whatever is free) every frame drawn is CPU the woken haptic worker
// may wait for. The page draws at most every budgetMs; each frame message says the worst tick
// lateness in the worker since its last frame, and a late tick doubles the budget (up to maxMs),
// an on-time one takes it back by stepMs towards minMs (maxMs below minMs: a fixed budget). Plain arithmetic on the times given,
// tested in virtual time (tests/host/wasm/frame_pacer_test.mjs).
export class FramePacer {
  constructor({ minMs = 0, maxMs = 0, lateMs = 0.5, stepMs = 5 } = {}) {
    this.minMs = minMs;
    this.maxMs = Math.max(minMs, maxMs);
    this.lateMs = lateMs;
    this.stepMs = stepMs;
    this.budgetMs = minMs;
    this.lastAt = -Infinity;
    this.skipped = 0;  // frames the budget held back
  }

  // The worker's word: its worst tick lateness (ms) since its previous frame.
  health(worstLateMs) {
    if (worstLateMs > this.lateMs) this.budgetMs = Math.min(this.maxMs, Math.max(this.budgetMs * 2, this.minMs + this.stepMs));
    else this.budgetMs = Math.max(this.minMs, this.budgetMs - this.stepMs);
  }

  // May the page draw at `now` (ms)? Counts the frames held back.
  due(now) {
    if (now - this.lastAt >= this.budgetMs) return true;
    this.skipped++;
    return false;
  }

  drew(now) { this.lastAt = now; }
}

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

// The page's frame cap: `fps` asked (?fps=; null when not), else `softwareFps` where WebGL
// rasterises on the CPU (each frame presented costs tens of ms of it there: docs/wasm/haptic-clock.md)
// and none on a GPU. The budget is a little (4 ms) under the period, so that animation frames at
// a 60 Hz display's rate that jitter still give every other one at 30, not every third; the
// worker writes its frames at the period itself (workerMs; 0: its own rate).
export function frameCap({ fps = null, software = false, softwareFps = 30 } = {}) {
  const f = Math.max(0, fps ?? (software ? softwareFps : 0));
  return { fps: f, minMs: f > 0 ? Math.max(0, 1000 / f - 4) : 0, workerMs: f > 0 ? 1000 / f : 0 };
}

// The trainee page's haptic clock (host/server/web/js/tick_clock.js, tick_stats.js) in virtual
// time, under node: no wall clock, no sleeps. A virtual now() (advancing 1 µs per call, so that
// a spin ends) and a sleep(ms) the test may make wake late, as a loaded system does.
//   node tick_clock_test.mjs host/server/web/js
import path from 'path';
import { pathToFileURL } from 'url';

const dir = path.resolve(process.argv[2]);
const { TickClock, MAX_CATCH_UP } = await import(pathToFileURL(path.join(dir, 'tick_clock.js')).href);
const { TickStats, BIN_MS } = await import(pathToFileURL(path.join(dir, 'tick_stats.js')).href);
const { FramePacer, frameCap } = await import(pathToFileURL(path.join(dir, 'frame_pacer.js')).href);
const { SharedFrame, FrameReader } = await import(pathToFileURL(path.join(dir, 'frame_share.js')).href);

let failures = 0;
function check(ok, what) {
  if (!ok) {
    failures++;
    console.log('FAIL: ' + what);
  }
}
const near = (a, b, tol) => Math.abs(a - b) <= tol;

// A virtual machine: `wake(ms)` says how late the sleep that starts at virtual time t wakes.
function machine({ tickMs = 0.1, wake = () => 0, spinMs, maxCatchUp } = {}) {
  const m = { t: 1000, sleeps: [], ticks: [] };
  m.clock = new TickClock({
    now: () => (m.t += 0.001),
    sleep: (ms) => { m.sleeps.push(ms); m.t += ms + wake(m.t); },
    ...(spinMs === undefined ? {} : { spinMs }),
    ...(maxCatchUp === undefined ? {} : { maxCatchUp }),
  });
  m.tick = (limit) => () => { m.ticks.push(m.t); m.t += tickMs; return m.ticks.length < limit; };
  m.run = (limit) => {
    m.clock.begin();
    const slices = [];
    for (;;) {
      const r = m.clock.slice(m.tick(limit));
      slices.push(m.t);
      if (r === 'over') return slices;
      m.t += 0.05;  // the event loop
    }
  };
  return m;
}

// 1. An unloaded machine: every tick at its deadline (within the spin's 1 µs steps), 1 ms apart,
//    the sleep ending spinMs before the deadline, a slice every 8 ms.
{
  const m = machine();
  m.run(100);
  const r = m.clock.stats.report();
  check(m.ticks.length === 100 && r.ticks === 100 && r.dropped === 0, 'unloaded: 100 ticks, none dropped: ' + JSON.stringify(r));
  const start = m.clock.startAt;
  check(m.ticks.every((at, k) => at >= start + k && at - (start + k) < 0.01), 'unloaded: each tick within 10 µs of its deadline');
  check(near(r.p50_ms, 1.005, 1e-9) && near(r.p99_ms, 1.005, 1e-9), 'unloaded: interval p50 and p99 are the 1.00-1.01 ms bin: ' + JSON.stringify(r));
  check(r.late_p99_ms < BIN_MS && r.late_ticks.after_sleep === 0, 'unloaded: no tick late');
  check(m.sleeps.every((ms) => ms > 0 && ms <= 1 - 0.2 + 1e-6), 'unloaded: each sleep ends 0.2 ms before its deadline');
  check(near(r.tick_p50_ms, 0.105, 1e-9), 'unloaded: a tick runs 0.1 ms (its bin): ' + r.tick_p50_ms);
}

// 2. One sleep that wakes 2.5 ms late (the system's scheduling): the two overdue ticks run back
//    to back at once (virtual time keeps up: nothing dropped), the late tick is put down to the
//    sleep and the other to catching up.
{
  let n = 0;
  const m = machine({ wake: () => (++n === 20 ? 2.5 : 0) });
  m.run(50);
  const r = m.clock.stats.report();
  check(r.ticks === 50 && r.dropped === 0, 'a 2.5 ms late wake: no tick dropped: ' + JSON.stringify(r));
  check(r.late_ticks.after_sleep === 1 && r.late_ticks.catch_up === 2 && r.late_ticks.after_yield === 0,
    'a 2.5 ms late wake: one late tick after the sleep, two caught up: ' + JSON.stringify(r.late_ticks));
  check(r.max_ms > 3 && r.max_ms < 3.5, 'a 2.5 ms late wake: the longest interval 3.3 ms: ' + r.max_ms);
  const start = m.clock.startAt;
  check(m.ticks.every((at, k) => at >= start + k), 'no tick before its deadline');
}

// 3. A 10 ms stall: MAX_CATCH_UP ticks run back to back, the rest are dropped, counted exactly.
{
  let n = 0;
  const m = machine({ wake: () => (++n === 5 ? 10 : 0) });
  m.run(40);
  const r = m.clock.stats.report();
  // The sleep before tick 5 ends 0.2 ms early, 10 ms late: at 14.8 ms, ticks 5..14 are due (10),
  // 4 of them run.
  check(r.dropped === 10 - MAX_CATCH_UP, 'a 10 ms stall: 6 ticks dropped: ' + r.dropped);
  check(r.late_ticks.after_sleep === 1 && r.late_ticks.catch_up >= MAX_CATCH_UP - 1, 'a 10 ms stall: one cause, caught up: ' + JSON.stringify(r.late_ticks));
  check(r.ticks === 40, 'a 10 ms stall: the run still has its 40 ticks');
}

// 3b. The same stall with a catch-up bound of 50 ticks (the page's): nothing dropped, the 10 due
//     ticks (5..14) run back to back, 0.1 ms each, which makes tick 15 late too (at 15.8 ms); from
//     tick 16 on the run keeps to its deadlines.
{
  let n = 0;
  const m = machine({ wake: () => (++n === 5 ? 10 : 0), maxCatchUp: 50 });
  m.run(40);
  const r = m.clock.stats.report();
  check(r.dropped === 0 && r.late_ticks.after_sleep === 1 && r.late_ticks.catch_up === 10,
    'a 10 ms stall, catch-up 50: none dropped, one cause, 10 caught up: ' + JSON.stringify(r));
  const start = m.clock.startAt;
  check(m.ticks.length === 40 && m.ticks.slice(16).every((at, k) => at - (start + 16 + k) < 0.01), 'after catching up, each tick at its deadline again');
}

// 4. Ticks that run long (3 ms each, as a heavy session would): late ticks come after ticks,
//    never from a sleep; spinMs 0 sleeps all the way.
{
  const m = machine({ tickMs: 3, spinMs: 0 });
  m.run(20);
  const r = m.clock.stats.report();
  check(r.late_ticks.after_sleep === 0 && r.late_ticks.after_ticks === 1, 'long ticks: lateness put down to the ticks: ' + JSON.stringify(r.late_ticks));
  check(r.dropped > 0, 'long ticks: ticks dropped (3 ms of work a 1 ms tick)');
  // The event loop still gets its turn every 8 ms however long the ticks run.
  const m2 = machine({ tickMs: 3 });
  m2.clock.begin();
  let yields = 0;
  while (m2.clock.slice(m2.tick(20)) !== 'over') yields++;
  check(yields >= 6, 'long ticks: the slice still yields (20 ticks of 3 ms: 6 or more yields), got ' + yields);
}

// 5. The slice yields to the event loop every 8 ms; a late tick after it is put down to the yield.
{
  const m = machine();
  let yields = 0;
  m.clock.begin();
  const tick = m.tick(30);
  for (;;) {
    if (m.clock.slice(tick) === 'over') break;
    yields++;
    m.t += yields === 2 ? 1.5 : 0.05;  // the second return to the event loop takes 1.5 ms (a frame, GC)
  }
  const r = m.clock.stats.report();
  check(yields === 3, 'a slice every 8 ms: 3 yields in 30 ticks, got ' + yields);
  check(r.late_ticks.after_yield === 1 && r.late_ticks.after_sleep === 0, 'the late tick after the slow event loop: ' + JSON.stringify(r.late_ticks));
}

// 6. The histogram's percentiles, exactly: 98 intervals of 1 ms and two of 5 ms.
{
  const s = new TickStats();
  let t = 0;
  s.start(t, t, 'sleep');
  for (let i = 0; i < 100; ++i) { t += i < 98 ? 1 : 5; s.start(t, t, 'sleep'); }
  const r = s.report();
  check(r.p50_ms === 1.005 && r.p99_ms === 5.005 && r.max_ms === 5, 'percentiles: ' + JSON.stringify(r));
}

// 7. The worst lateness since the last frame (the worker's word to the page), taken afresh.
{
  const s = new TickStats();
  s.start(10, 10, 'sleep');
  s.start(11.3, 11, 'sleep');
  s.start(12.1, 12, 'sleep');
  check(near(s.takeWorst(), 0.3, 1e-9), 'the worst lateness since the start: 0.3 ms');
  s.start(13.05, 13, 'sleep');
  check(near(s.takeWorst(), 0.05, 1e-9), 'the worst lateness since the last take: 0.05 ms');
  check(s.takeWorst() === 0, 'nothing since the last take: 0');
}

// 8. The page's frame budget (frame_pacer.js): at most every minMs; a late tick doubles it up to
// maxMs, on-time frames take it back stepMs at a time; a frame held back is counted.
{
  const p = new FramePacer({ minMs: 40, maxMs: 200, lateMs: 0.5, stepMs: 10 });
  check(p.due(0), 'the first frame is due');
  p.drew(0);
  check(!p.due(39) && p.due(40), 'the next at 40 ms, not before');
  p.health(0.6);
  check(p.budgetMs === 80, 'a late tick doubles the budget: ' + p.budgetMs);
  for (let i = 0; i < 5; ++i) p.health(3);
  check(p.budgetMs === 200, 'up to maxMs: ' + p.budgetMs);
  p.health(0.5);
  check(p.budgetMs === 190, 'a tick on time (0.5 ms is not late) takes 10 ms back: ' + p.budgetMs);
  for (let i = 0; i < 100; ++i) p.health(0);
  check(p.budgetMs === 40, 'down to minMs: ' + p.budgetMs);
  check(p.skipped === 1, 'one frame held back: ' + p.skipped);
  const off = new FramePacer();
  off.drew(5);
  off.health(10);
  check(off.budgetMs === 0 && off.due(5), 'maxMs 0: no budget, every frame due: ' + off.budgetMs);
}

// 8b. The page's frame cap (frameCap): 30 a second on a software rasteriser unless ?fps= says
// otherwise, none on a GPU; at 30 the budget (29.3 ms) takes every other 60 Hz animation frame
// even when they jitter by up to 3 ms (a budget of the whole period would skip to every third),
// and the worker writes at the period.
{
  const soft = frameCap({ software: true });
  check(soft.fps === 30 && near(soft.workerMs, 1000 / 30, 1e-9), 'software: 30 a second, the worker every 33.3 ms');
  const p = new FramePacer({ minMs: soft.minMs });
  let drawn = 0;
  let last = -1;
  for (let k = 0; k < 60; ++k) {
    const t = k * 1000 / 60 + [0, 2, -2, 3, -3, 1][k % 6];  // animation frames 16.7 ms apart, jittering up to 3 ms
    if (p.due(t)) { p.drew(t); ++drawn; check(last < 0 || k - last === 2, 'every other animation frame: ' + k + ' after ' + last); last = k; }
  }
  check(drawn === 30, 'software: 30 of 60 animation frames drawn: ' + drawn);
  check(frameCap({ software: false }).fps === 0 && frameCap().minMs === 0 && frameCap().workerMs === 0, 'a GPU: no cap');
  check(frameCap({ fps: 0, software: true }).fps === 0, '?fps=0: no cap on software either');
  check(frameCap({ fps: 5, software: false }).minMs === 196, '?fps=5 on a GPU: 196 ms');
}

// 9. The shared frame (frame_share.js): the page takes a whole frame once; none while the worker
// is writing (odd sequence) or when it wrote again during the copy; the capacities travel with it.
{
  const w = SharedFrame.create(8, 16);
  const r = new FrameReader(w.buffer);
  check(r.take() === null, 'nothing before the first frame');
  const text = (s, to) => { const b = new TextEncoder().encode(s); to.set(b); return b.length; };
  w.begin();
  w.f32.set([1, 2, 3]);
  const mb = text('{"a":1}', w.metrics);
  const db = text('{"hints":[]}', w.drive);
  w.f64[0] = 0.75;
  check(r.take() === null, 'no frame while the worker writes it');
  w.setCounts(3, mb, db, 0);
  w.end();
  const f = r.take();
  check(f && f.data.length === 3 && f.data[2] === 3 && f.metricsText === '{"a":1}' && f.driveText === '{"hints":[]}' &&
    f.lateMs === 0.75 && f.fluoro === null, 'the frame as written: ' + JSON.stringify(f && [...f.data]));
  check(r.take() === null, 'taken once');
  w.begin(); w.f32[0] = 9; w.setCounts(1, mb, db, 1); w.end();
  const g = r.take();
  check(g && g.data[0] === 9 && g.fluoro && g.fluoro.header.length === 56 && g.fluoro.carm.length === 9, 'the next, with the fluoroscopy');
  const torn = new FrameReader(w.buffer);
  const load = Atomics.load;
  let calls = 0;
  Atomics.load = (a, i) => { const v = load(a, i); return ++calls === 2 ? v + 2 : v; };  // the worker wrote during the copy
  check(torn.take() === null, 'a frame rewritten during the copy is not taken');
  Atomics.load = load;
  check(torn.take() !== null, 'the next look takes it');
  check(!w.fits(9, 0, 0) && w.fits(8, 16, 16), 'the capacities: 8 floats, 16 bytes');
}

if (failures) {
  console.log(failures + ' check(s) failed');
  process.exit(1);
}
console.log('tick clock: all checks passed');

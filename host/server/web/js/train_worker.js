// The trainee page's haptic tick: a dedicated Web Worker that owns the session (cathbox-trainee,
// WebAssembly, from /wasm/) and its clock. Never the page's thread.
//
// Clocks (the page's `clock` option):
//   'real'    — 1 kHz against performance.now(): the ticks that are due run, then the worker
//               sleeps to the next deadline with Atomics.wait (sub-millisecond, unlike timers),
//               and every 8 ms it returns to its event loop (messages; the record writer's
//               file calls, which its thread hands to this one). More than 4 ticks late: the
//               overdue ones are dropped (counted), as the native haptic thread does. The
//               interval between consecutive ticks is measured (jitter: p50, p99, max).
//   'virtual' — no clock of its own: the page says `advance N` (its "Run N ticks" control) and
//   exactly N ticks run.
// Either way a tick reads the keys' speeds the page wrote into shared memory (Float64Array:
// insertion mm/s, rotation rad/s) just before it runs, as the native trainer's haptic thread
// reads its KeyboardInput.
//
// The box bridge (?box=ws://...): its driver (js/train_box.js) runs here, between tick slices,
// writing the keys' speeds and sending the force law at most 8 ms apart (the box's watchdog is
// 50 ms); each frame carries its report, and box_note messages its state for the page.
//
// Messages in: open {caseFile, caseText, hclmFile, hclmText, mesh (CBXMESH2 bytes), clock, keys, box},
// advance {ticks}, next_tool, end, replay {record (.cbxrec bytes), mesh (CBXMESH2 bytes)}. Out: ready {summary, open_ms}, frame {data: Float32Array, metrics},
// advanced {ticks}, over {summary, record (bytes), jitter},
// replayed {passed, figures {ticks, recorded_ticks, hashes_checked, mismatch_tick}, message, ms}, error {message}.
'use strict';

const SLICE_MS = 8;
const MAX_CATCH_UP = 4;  // as session::HapticPacer
const FRAME_MS = 16;
const BIN_MS = 0.01;  // interval histogram: 10 µs bins up to 100 ms
const BINS = 10000;

let mod = null;
let fn = null;
let keys = null;
let clock = 'real';
let over = false;
const sleepCell = new Int32Array(new SharedArrayBuffer(4));
const histogram = new Uint32Array(BINS + 1);
let lastTickAt = -1;
let intervals = 0;
let maxInterval = 0;
let dropped = 0;
let box = null;  // the bridge's BoxDriver, or null
let latest = null;  // the newest snapshot's hand figures, for the box driver

function fail(message) { postMessage({ type: 'error', message: String(message) }); }

function loadModule() {
  try {
    importScripts('/wasm/cathbox-trainee.js');
  } catch (_) {
    throw new Error('/wasm/cathbox-trainee.js: the WebAssembly session is not served here (cathbox-server --wasm DIR)');
  }
  return self.CathboxTrainee({
    locateFile: (path) => '/wasm/' + path,
    mainScriptUrlOrBlob: '/wasm/cathbox-trainee.js',
    print: () => {},
    printErr: (line) => console.warn('cathbox-trainee: ' + line),
  });
}

function bind(m) {
  const c = (name, ret, args) => m.cwrap(name, ret, args);
  return {
    open: c('cbx_open', 'number', ['string', 'string', 'string']),
    error: c('cbx_error', 'string', []),
    speeds: c('cbx_set_speeds', null, ['number', 'number']),
    nextTool: c('cbx_next_tool', null, []),
    end: c('cbx_end_run', null, []),
    step: c('cbx_step', 'number', ['number']),
    over: c('cbx_over', 'number', []),
    snapshot: c('cbx_snapshot', 'number', []),
    snapshotData: c('cbx_snapshot_data', 'number', []),
    snapshotMetrics: c('cbx_snapshot_metrics', 'string', []),
    closeRecord: c('cbx_close_record', 'number', []),
    summary: c('cbx_summary', 'string', []),
    replayCheck: c('cbx_replay_check', 'number', ['string', 'string']),
    replaySummary: c('cbx_replay_summary', 'string', []),
  };
}

// One tick, with the keys as they are now.
function tick() {
  fn.speeds(keys[0], keys[1]);
  fn.step(1);
  if (fn.over()) over = true;
}

function measure(now) {
  if (lastTickAt >= 0) {
    const d = now - lastTickAt;
    histogram[Math.min(BINS, Math.floor(d / BIN_MS))]++;
    intervals++;
    if (d > maxInterval) maxInterval = d;
  }
  lastTickAt = now;
}

function percentile(p) {
  if (intervals === 0) return null;
  const want = Math.ceil(p * intervals);
  let seen = 0;
  for (let i = 0; i <= BINS; ++i) {
    seen += histogram[i];
    if (seen >= want) return (i + 0.5) * BIN_MS;
  }
  return maxInterval;
}

function postFrame() {
  const n = fn.snapshot();
  const at = fn.snapshotData() >> 2;
  // The memory may have grown (a new shared buffer): a call returning a string makes the
  // runtime renew its views (GROWABLE_HEAP_U8), then HEAPF32 covers the snapshot.
  if (at + n > mod.HEAPF32.length) fn.error();
  const data = new Float32Array(n);
  data.set(mod.HEAPF32.subarray(at, at + n));
  latest = { insertion_mm: data[2], rotation_rad: data[3], hand_force_mN: data[4], torque_mNmm: data[5] };
  postMessage({ type: 'frame', data, metrics: JSON.parse(fn.snapshotMetrics()), box: box ? box.report() : null }, [data.buffer]);
}

function finish() {
  if (box) box.stop();
  postFrame();
  if (!fn.closeRecord()) return fail('record: ' + fn.error());
  const summary = JSON.parse(fn.summary());
  const record = mod.FS.readFile('/run/run.cbxrec');
  const jitter = clock === 'real'
    ? { ticks: intervals + 1, p50_ms: percentile(0.5), p99_ms: percentile(0.99), max_ms: maxInterval, dropped }
    : null;
  postMessage({ type: 'over', summary, record: record.buffer, jitter }, [record.buffer]);
}

// The real clock: tick k is due at start + k ms.
let start = 0;
let due = 0;
const yielder = new MessageChannel();
yielder.port1.onmessage = () => slice();
let lastFrameAt = 0;

function slice() {
  const sliceEnd = performance.now() + SLICE_MS;
  for (;;) {
    let now = performance.now();
    const late = Math.floor(now - start) - due + 1;  // ticks due now
    if (late > MAX_CATCH_UP) {
      dropped += late - MAX_CATCH_UP;
      due += late - MAX_CATCH_UP;
    }
    while (!over && start + due <= now) {
      measure(now);
      tick();
      ++due;
      now = performance.now();
    }
    if (over) return finish();
    if (now >= sliceEnd) break;
    Atomics.wait(sleepCell, 0, 0, start + due - now);
  }
  if (performance.now() - lastFrameAt >= FRAME_MS) {
    lastFrameAt = performance.now();
    postFrame();
  }
  yielder.port2.postMessage(0);  // back to the event loop, then on
}

// The bridge's driver; a failure leaves the keyboard (said in a box_note).
async function openBox(url) {
  const note = (text) => postMessage({ type: 'box_note', text });
  try {
    const [{ BoxDriver }, { WebSocketBox }] = await Promise.all([import('/js/train_box.js'), import('/js/box_transport.js')]);
    box = new BoxDriver({ keys, sessionAt: () => (over ? null : latest), onChange: note });
    await box.connect(new WebSocketBox(url));
  } catch (err) {
    note('no box: ' + (err && err.message ? err.message : err) + ' (the keyboard drives the tool)');
  }
}

async function ensureModule() {
  if (!mod) {
    mod = await loadModule();
    fn = bind(mod);
  }
}

// Any rig's record (native or a page's) replayed with every state hash checked; the run, if one
// is open, is left alone.
async function replay(m) {
  await ensureModule();
  const FS = mod.FS;
  try { FS.mkdir('/check'); } catch (_) { /* there */ }
  FS.writeFile('/check/record.cbxrec', new Uint8Array(m.record));
  FS.writeFile('/check/collision.cbxmesh', new Uint8Array(m.mesh));
  const t0 = performance.now();
  const passed = fn.replayCheck('/check/record.cbxrec', '/check/collision.cbxmesh') === 1;
  const ms = performance.now() - t0;
  const figures = JSON.parse(fn.replaySummary());
  const message = passed ? '' : fn.error();
  FS.unlink('/check/record.cbxrec');
  FS.unlink('/check/collision.cbxmesh');
  postMessage({ type: 'replayed', passed, figures, message, ms });
}

async function open(m) {
  const t0 = performance.now();
  await ensureModule();
  const FS = mod.FS;
  for (const dir of ['/case', '/run']) { try { FS.mkdir(dir); } catch (_) { /* there */ } }
  FS.writeFile('/case/' + m.caseFile, m.caseText);
  if (m.hclmFile) FS.writeFile('/case/' + m.hclmFile, m.hclmText);
  FS.writeFile('/case/collision.cbxmesh', new Uint8Array(m.mesh));
  if (!fn.open('/case/' + m.caseFile, '/case/collision.cbxmesh', '/run/run.cbxrec')) return fail(fn.error());
  keys = new Float64Array(m.keys);
  clock = m.clock === 'virtual' ? 'virtual' : 'real';
  over = false;
  if (m.box) await openBox(m.box);
  postFrame();
  postMessage({ type: 'ready', summary: JSON.parse(fn.summary()), open_ms: performance.now() - t0 });
  if (clock === 'real') {
    start = performance.now();
    due = 0;
    slice();
  }
}

onmessage = (e) => {
  const m = e.data;
  try {
    if (m.type === 'open') {
      open(m).catch((err) => fail(err && err.message ? err.message : err));
    } else if (m.type === 'replay') {
      replay(m).catch((err) => fail(err && err.message ? err.message : err));
    } else if (!fn) {
      fail('no session open');
    } else if (m.type === 'advance') {
      if (clock !== 'virtual') return fail('advance: the worker runs on its own clock');
      let ran = 0;
      while (ran < m.ticks && !over) { tick(); ++ran; }
      if (!over) postFrame();  // the page shows the state the step ended at before it says so
      postMessage({ type: 'advanced', ticks: ran });
      if (over) finish();
    } else if (m.type === 'next_tool') {
      fn.nextTool();
    } else if (m.type === 'end') {
      fn.end();
      if (clock === 'virtual' && !over) { tick(); if (over) finish(); }
    }
  } catch (err) {
    fail(err && err.message ? err.message : err);
  }
};

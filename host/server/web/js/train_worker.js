// The trainee page's haptic tick: a dedicated Web Worker that owns the session (cathbox-trainee,
// WebAssembly, from /wasm/) and its clock. Never the page's thread.
//
// Clocks (the page's `clock` option):
//   'real'    — 1 kHz against performance.now() (js/tick_clock.js): the ticks that are due run,
//               then the worker sleeps to the next deadline with Atomics.wait (sub-millisecond,
//               unlike timers) and spins on performance.now() for the last 0.2 ms (the page's
//               `spin` option, ms), and every 8 ms it returns to its event loop (messages; the
//               record writer's file calls, which its thread hands to this one). Up to 50 overdue
//               ticks run back to back in the session's virtual time (the native haptic thread
//               stops at 4); beyond that they are dropped (counted). The timing is measured
//               (js/tick_stats.js: interval, lateness, each tick's run time, what the late ticks
//               came after) and posted at the end (the page's clock note shows it).
//   'virtual' — no clock of its own: the page says `advance N` (its "Run N ticks" control) and
//   exactly N ticks run.
// Either way a tick reads the keys the page wrote into shared memory (Float64Array: insertion
// mm/s, rotation rad/s, 1 while a movement key is held) just before it runs, as the native
// trainer's haptic thread reads its KeyboardInput. U and E (the stent retriever's drives,
// cathbox-trainer's app::DeviceDrive compiled into the module) come as `drive` messages and are
// decided at the next tick; refused while a box drives the tools. Each frame carries the drive's
// HUD lines and notes.
//
// The box, over the bridge (?box=ws://...) or WebHID: its driver (js/train_box.js) runs here,
// between tick slices, writing the keys' speeds and sending the force law at most 8 ms apart (the
// box's watchdog is 50 ms); each frame carries its report, and box_note messages its state for the
// page. For WebHID the page only asks Chromium for the box (the chooser needs a click there) and
// says box_hid; this worker finds the permitted box with navigator.hid.getDevices() and owns its
// reports (inputreport, sendReport, receiveFeatureReport): they never cross the page's thread.
//
// Messages in: open {caseFile, caseText, hclmFile, hclmText, mesh (CBXMESH2 bytes), clock, keys, box, frameMs},
// advance {ticks}, next_tool, drive {unsheathe, retrieve} (U / E pressed), end, replay {record (.cbxrec bytes), mesh (CBXMESH2 bytes)},
// box_hid (the page was allowed a WebHID box: open it here), fluoro_keys {bits}
// (the fluoroscopy keys held), fluoro_size {size: [w, h] or null}, carm {what: 'angles' | 'geometry' |
// 'rate', values} (the C-arm panel's edit, posted as the native panel posts it). Out: ready {summary,
// open_ms, fluoro, projections (the C-arm panel's: [{name, lao, cranial}])}, carm_note {text} (an
// edit refused: its line; '' when taken),
// fluoro_vessel {vertices, indices, shaders: the fluoroscopy's GLSL texts}, frames {buffer: the shared
// frame's SharedArrayBuffer (js/frame_share.js), at open and when a frame outgrows it}; the frames
// themselves are written there, not posted; fluoro_data {header, carm, phantom?, floats?, indices?}
// (the phantom or the scenes, when new), box {report} (each frame while a box is connected),
// advanced {ticks}, over {summary, record (bytes), jitter},
// replayed {passed, figures {ticks, recorded_ticks, hashes_checked, mismatch_tick}, message, ms},
// box_note {text}, error {message}.
'use strict';

// A frame every FRAME_MS, or at the page's own frame rate when it draws less often (its `frameMs`
// at open: ?fps=, 30 a second on a software rasteriser): a frame the page never takes is the
// worker's time spent (the snapshot, the metrics' JSON, the fluoroscopy's inputs) between ticks.
const FRAME_MS = 16;
let frameMs = FRAME_MS;
// Overdue ticks run back to back up to 50 (a tick is ~35 µs in wasm: 50 take ~2 ms), so a stall
// of the worker's thread up to 50 ms costs no simulated time; beyond, they are dropped.
const CATCH_UP_TICKS = 50;

let mod = null;
let fn = null;
let keys = null;
let clock = 'real';
let over = false;
const sleepCell = new Int32Array(new SharedArrayBuffer(4));
const clockModule = import('/js/tick_clock.js');  // fetched while the session loads
const frameModule = import('/js/frame_share.js');
let frameShare = null;  // js/frame_share.js, once loaded
const HEADER_DOUBLES = 56;
let ticker = null;  // the real clock's TickClock
let box = null;  // the box's BoxDriver (bridge or WebHID), or null
const latest = { insertion_mm: 0, rotation_rad: 0, hand_force_mN: 0, torque_mNmm: 0 };  // the newest snapshot's hand figures, for the box driver
let sessionOpen = false;
let hidAsked = false;  // box_hid came before the session opened

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
    tick: c('cbx_tick', 'number', ['number', 'number', 'number', 'number']),
    driveKeys: c('cbx_drive_keys', null, ['number', 'number']),
    drive: c('cbx_drive', 'string', []),
    nextTool: c('cbx_next_tool', null, []),
    end: c('cbx_end_run', null, []),
    noteDropped: c('cbx_note_dropped', null, ['number']),
    over: c('cbx_over', 'number', []),
    snapshot: c('cbx_snapshot', 'number', []),
    snapshotData: c('cbx_snapshot_data', 'number', []),
    snapshotMetrics: c('cbx_snapshot_metrics', 'string', []),
    closeRecord: c('cbx_close_record', 'number', []),
    summary: c('cbx_summary', 'string', []),
    replayCheck: c('cbx_replay_check', 'number', ['string', 'string']),
    replaySummary: c('cbx_replay_summary', 'string', []),
    boxConfigure: c('cbx_box_configure', null, ['number', 'number', 'number', 'number']),
    boxCommand: c('cbx_box_command', 'number', ['number', 'number', 'number', 'number', 'number', 'number', 'number']),
    boxCommandBytes: c('cbx_box_command_bytes', 'number', []),
    fluoroOpen: c('cbx_fluoro_open', 'number', []),
    fluoroKeys: c('cbx_fluoro_keys', null, ['number']),
    fluoroFrame: c('cbx_fluoro_frame', 'number', ['number', 'number']),
    fluoroRequest: c('cbx_fluoro_request', 'number', ['number', 'number']),
    fluoroData: c('cbx_fluoro_data', 'number', ['number']),
    fluoroSize: c('cbx_fluoro_size', 'number', ['number']),
    fluoroShader: c('cbx_fluoro_shader', 'string', ['number']),
    carmProjections: c('cbx_carm_projections', 'string', []),
    carmSet: c('cbx_carm_set', 'number', ['number', 'number', 'number', 'number', 'number']),
    carmState: c('cbx_carm_state', 'number', []),
  };
}

// One tick, with the keys as they are now (speeds, a movement key held) and whether a box drives
// the tools; the stent's U / E drive (app::DeviceDrive, in the module) decides first.
function tick() {
  if (!fn.tick(keys[0], keys[1], keys[2], box && box.live ? 1 : 0)) over = true;
}

// A copy of n elements of the module's memory at byte address `at` (HEAPF32, HEAPF64, HEAPU32).
// The memory may have grown (a new shared buffer): a call returning a string makes the runtime
// renew its views (GROWABLE_HEAP_U8), then the view covers them.
function copyHeap(heap, at, n) {
  const i = at / mod[heap].BYTES_PER_ELEMENT;
  if (i + n > mod[heap].length) fn.error();
  return mod[heap].slice(i, i + n);
}

// The fluoroscopy (wasm/browser_fluoro.hpp, js/fluoro_view.js): the page's image size while it
// shows it (null: the 3D view), and what it was last sent.
let fluoroOn = false;
let fluoroSize = null;
let fluoroSent = { scene: -1, phantom: -1 };

// The fluoroscopy's image for this frame, made before the frame's write (so that the page's read
// of the shared frame never waits on it): on the real clock by the module's fluoroscopy thread
// (cbx_fluoro_request: the snapshot handed over, its newest image taken; wasm/fluoro_thread.hpp),
// so that no tick waits for an image's work (the inputs, a pulse's tool tubes, a new pose's
// phantom); on the virtual clock here (cbx_fluoro_frame: the image of this very snapshot).
// The header's address, or 0 (not shown, or no image made yet).
function fluoroImage() {
  if (!fluoroOn || !fluoroSize) return 0;
  return clock === 'real' ? fn.fluoroRequest(fluoroSize[0], fluoroSize[1]) : fn.fluoroFrame(fluoroSize[0], fluoroSize[1]);
}

// The header and the C-arm into the shared frame's doubles (1.., 57..), inside the frame's write.
function fluoroHeader(f64, h, c) {
  const heap = mod.HEAPF64;
  for (let i = 0; i < HEADER_DOUBLES; ++i) f64[1 + i] = heap[(h >> 3) + i];
  for (let i = 0; i < 9; ++i) f64[1 + HEADER_DOUBLES + i] = heap[(c >> 3) + i];
}

// The phantom and the scenes, when new, as a fluoro_data message with their own header
// (js/fluoro_view.js keeps the scenes' header with them), after the frame's write.
function fluoroData(h, c) {
  const heap = mod.HEAPF64;
  const newPhantom = heap[(h >> 3) + 43] !== fluoroSent.phantom;
  const newScene = heap[h >> 3] && heap[(h >> 3) + 42] !== fluoroSent.scene;
  if (!newPhantom && !newScene) return;
  const out = { type: 'fluoro_data', header: copyHeap('HEAPF64', h, HEADER_DOUBLES), carm: copyHeap('HEAPF64', c, 9) };
  if (newPhantom) {
    out.phantom = copyHeap('HEAPF32', fn.fluoroData(2), fn.fluoroSize(2));
    fluoroSent.phantom = out.header[43];
  }
  if (newScene) {
    out.floats = copyHeap('HEAPF32', fn.fluoroData(3), fn.fluoroSize(3));
    out.indices = copyHeap('HEAPU32', fn.fluoroData(4), fn.fluoroSize(4));
    fluoroSent.scene = out.header[42];
  }
  postMessage(out, ['header', 'phantom', 'floats', 'indices'].filter((k) => out[k]).map((k) => out[k].buffer));
}

// The frame (js/frame_share.js): the snapshot floats, the metrics' and the drive's JSON bytes, the
// worst lateness and the fluoroscopy's header and C-arm, copied from the module's memory into the
// shared frame with plain loops (no view, array or string made); the page reads it on its
// animation frame. What is new and large (the phantom, the scenes) and the box's report go as a
// message, and a frame that outgrows the buffer makes a bigger one (said in a message).
const FRAME_FLOATS = 1 << 16;
const FRAME_BYTES = 1 << 14;
let shared = null;  // the SharedFrame, made at open
let framed = false;  // a frame was written (the box driver's hand figures are the session's)

function heapFits(end) { if (end > mod.HEAPU8.length) fn.error(); }  // a string call renews grown views

function cstrLength(at) {
  const h = mod.HEAPU8;
  let e = at;
  while (h[e] !== 0) ++e;
  return e - at;
}

function copyBytes(from, n, to) {
  const h = mod.HEAPU8;
  for (let i = 0; i < n; ++i) to[i] = h[from + i];
}

function ensureShared(n, mb, db) {
  if (shared && shared.fits(n, mb, db)) return;
  shared = frameShare.SharedFrame.create(Math.max(FRAME_FLOATS, 2 * n), Math.max(FRAME_BYTES, 2 * mb, 2 * db));
  postMessage({ type: 'frames', buffer: shared.buffer });
}

function postFrame() {
  const n = fn.snapshot();
  const at = fn.snapshotData();
  heapFits(at + 4 * n);
  const metricsAt = mod._cbx_snapshot_metrics();
  heapFits(metricsAt);
  const mb = cstrLength(metricsAt);
  ensureShared(n, mb, 0);
  const h = fluoroImage();
  const c = h ? fn.carmState() : 0;
  if (h) heapFits(Math.max(h + 8 * HEADER_DOUBLES, c + 72));
  shared.begin();
  const f32 = shared.f32;
  const heap = mod.HEAPF32;
  const i0 = at >> 2;
  for (let i = 0; i < n; ++i) f32[i] = heap[i0 + i];
  copyBytes(metricsAt, mb, shared.metrics);  // before cbx_drive: the module's one text buffer
  const driveAt = mod._cbx_drive();
  const db = Math.min(cstrLength(driveAt), shared.drive.length);
  copyBytes(driveAt, db, shared.drive);
  if (h) fluoroHeader(shared.f64, h, c);
  shared.f64[0] = ticker ? ticker.stats.takeWorst() : 0;  // the page paces its drawing by it (js/frame_pacer.js)
  shared.setCounts(n, mb, db, h ? 1 : 0);
  shared.end();
  if (h) fluoroData(h, c);
  latest.insertion_mm = f32[2];
  latest.rotation_rad = f32[3];
  latest.hand_force_mN = f32[4];
  latest.torque_mNmm = f32[5];
  framed = true;
  if (box) postMessage({ type: 'box', report: box.report() });
}

function finish() {
  if (box) box.stop();
  postFrame();
  if (!fn.closeRecord()) return fail('record: ' + fn.error());
  const summary = JSON.parse(fn.summary());
  const record = mod.FS.readFile('/run/run.cbxrec');
  const jitter = clock === 'real' ? ticker.stats.report() : null;
  postMessage({ type: 'over', summary, record: record.buffer, jitter }, [record.buffer]);
}

// The real clock (js/tick_clock.js): one slice of ticks, a frame every frameMs, then the event loop.
const yielder = new MessageChannel();
yielder.port1.onmessage = () => slice();
let lastFrameAt = 0;
// The ticks the clock dropped are told to the session before the next runs (its record's end
// block and metrics keep the total: host/session/README.md, "Haptic ticks dropped").
let toldDropped = 0;
const runTick = () => {
  if (ticker.stats.dropped !== toldDropped) fn.noteDropped(toldDropped = ticker.stats.dropped);
  tick();
  return !over;
};

function slice() {
  if (ticker.slice(runTick) === 'over') return finish();
  if (performance.now() - lastFrameAt >= frameMs) {
    lastFrameAt = performance.now();
    postFrame();
  }
  yielder.port2.postMessage(0);  // back to the event loop, then on
}

// The box's command from the held tool's law (cbx_box_command: the native BoxHand's shaping and
// encoding), for the box's driver here.
const boxLaw = {
  configure: (c, periodMs) => fn.boxConfigure(c.full_scale_mN, c.slew_mN_per_ms, periodMs, c.mode),
  command: (a) => {
    const status = fn.boxCommand(a.offset_mm, a.offset_rad, a.force_mN, a.speed_mm_s, a.seq, a.time_us, a.flags);
    if (status !== 0) throw new Error('OUT command: status ' + status);
    const at = fn.boxCommandBytes();
    return mod.HEAPU8.slice(at, at + 64);
  },
};

// The box's driver over the bridge (url) or WebHID (null); a failure leaves the keyboard (said in a
// box_note). Called once the session is open.
async function openBox(url) {
  const note = (text) => postMessage({ type: 'box_note', text });
  try {
    const [{ BoxDriver, SEND_MS }, { WebSocketBox, WebHidBox }] = await Promise.all([import('/js/train_box.js'), import('/js/box_transport.js')]);
    if (box) box.stop();
    box = new BoxDriver({ keys, sessionAt: () => (over || !framed ? null : latest), onChange: note,
      law: { configure: (c) => boxLaw.configure(c, SEND_MS), command: boxLaw.command } });
    await box.connect(url ? new WebSocketBox(url) : new WebHidBox());
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
  sessionOpen = true;
  frameShare = await frameModule;
  keys = new Float64Array(m.keys);
  clock = m.clock === 'virtual' ? 'virtual' : 'real';
  frameMs = Math.max(FRAME_MS, Number(m.frameMs) || 0);
  fluoroOn = fn.fluoroOpen() === 1;
  fluoroSent = { scene: -1, phantom: -1 };
  fluoroSize = m.fluoroSize || null;
  if (fluoroOn) {
    const glsl = ['version', 'sceneVs', 'sceneFs', 'fullVs', 'compositeFs', 'scaleFs'];
    postMessage({ type: 'fluoro_vessel', vertices: copyHeap('HEAPF32', fn.fluoroData(0), fn.fluoroSize(0)),
      indices: copyHeap('HEAPU32', fn.fluoroData(1), fn.fluoroSize(1)),
      shaders: Object.fromEntries(glsl.map((name, i) => [name, fn.fluoroShader(i)])) });
  }
  over = false;
  if (m.box) await openBox(m.box);
  else if (hidAsked) await openBox(null);
  postFrame();
  postMessage({ type: 'ready', summary: JSON.parse(fn.summary()), open_ms: performance.now() - t0, fluoro: fluoroOn,
    projections: fluoroOn ? JSON.parse(fn.carmProjections()) : [] });
  if (clock === 'real') {
    const { TickClock } = await clockModule;
    ticker = new TickClock({
      now: () => performance.now(),
      sleep: (ms) => Atomics.wait(sleepCell, 0, 0, ms),
      maxCatchUp: CATCH_UP_TICKS,
      ...(Number.isFinite(m.spinMs) ? { spinMs: m.spinMs } : {}),
    });
    ticker.begin();
    fn.noteDropped(toldDropped = 0);  // a run on the real clock: none dropped yet
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
    } else if (m.type === 'box_hid') {
      if (sessionOpen) openBox(null); else hidAsked = true;
    } else if (!fn) {
      fail('no session open');
    } else if (m.type === 'advance') {
      if (clock !== 'virtual') return fail('advance: the worker runs on its own clock');
      let ran = 0;
      while (ran < m.ticks && !over) { tick(); ++ran; }
      if (!over) postFrame();  // the page shows the state the step ended at before it says so
      postMessage({ type: 'advanced', ticks: ran });
      if (over) finish();
    } else if (m.type === 'fluoro_keys') {
      fn.fluoroKeys(m.bits);
    } else if (m.type === 'carm') {
      const v = [0, 0, 0, 0].map((_, i) => Number(m.values[i] ?? 0));
      const done = fn.carmSet({ angles: 0, geometry: 1, rate: 2 }[m.what], ...v);
      postMessage({ type: 'carm_note', text: done < 0 ? fn.error() : '' });
    } else if (m.type === 'fluoro_size') {
      fluoroSize = m.size;  // the next frame projects the phantom for it if it is new
    } else if (m.type === 'drive') {
      fn.driveKeys(m.unsheathe ? 1 : 0, m.retrieve ? 1 : 0);
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

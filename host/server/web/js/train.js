// The trainee's simulator in the browser: my assignments, a case opened from the server (the
// bundle, the surface to draw, the collision surface the session runs on), the session in a
// dedicated Web Worker (js/train_worker.js: WebAssembly, its own 1 kHz clock), the keyboard as in
// cathbox-trainer, a global and a local 3D view with the HUD, the end-of-run metrics, and the
// record uploaded as the native trainer uploads it (POST /results?assignment=ID). The run is
// streamed live to instructors as rig `browser-USER` (js/train_live.js).
//
// A box (js/train_box.js over js/box_transport.js, driven in the haptic worker) drives the held tool
// in place of the keys: ?box=ws://HOST:PORT uses cathbox-box-bridge in front of cathbox-emu; where
// the browser has WebHID, "Connect box" asks Chromium for the box (the page's only part: the chooser
// needs a click) and the worker opens it; elsewhere the page says so and keeps the keys.
//
// /train.html?spin=MS: the worker's clock spins the last MS before each deadline (js/tick_clock.js).
// /train.html?fps=N: frames taken and drawn at most N a second (0: every animation frame; default
// SOFTWARE_FPS on a software rasteriser, scene.js glRenderer; js/frame_pacer.js frameCap).
// /train.html?frame_ms=MIN&frame_max_ms=MAX: the adaptive frame budget (js/frame_pacer.js; off).
// /train.html?scale=S (0.25-1): the views drawn at S of the page's pixel density, stretched to size.
// /train.html?view=fluoro|3d: the main view, as cathbox-trainer's --view (default: fluoroscopy for a
// `realistic` case); the page's button switches it. The fluoroscopic image is js/fluoro_view.js
// (the native renderer's shaders in WebGL2) over inputs the worker makes (host/wasm browser_fluoro).
// /train.html?clock=virtual: the worker has no clock of its own; the page's "Run N ticks" control
// runs exactly N (a run that is the same on any machine: the browser test drives the page so).
//
// No test hook: what a test checks is on the page (the status, the HUD's figures, the notes under
// the keys, the box's figures, the end card, the record check's line).
import { requireUser, api, guarded, showError, el } from './api.js';
import { VesselView, loadMesh, glRenderer } from './scene.js';
import { speedsFor, isControlKey, fluoroBits, steering } from './train_keys.js';
import { FluoroView, H } from './fluoro_view.js';
import { CArmPanel } from './carm_panel.js';
import { Histogram } from './tick_stats.js';
import { LiveRig } from './train_live.js';
import { showEnd } from './train_end.js';
import { offerBox, boxNote, showBoxReport } from './train_box_panel.js';
import { FramePacer, frameCap } from './frame_pacer.js';
import { unpack, hudText, fit } from './train_snapshot.js';
import { FrameReader } from './frame_share.js';

const user = requireUser(['trainee']);
const params = new URLSearchParams(location.search);
const clock = params.get('clock') === 'virtual' ? 'virtual' : 'real';
const numberParam = (name, fallback) => (params.has(name) && Number.isFinite(Number(params.get(name))) ? Number(params.get(name)) : fallback);
const SOFTWARE_FPS = 30;
const FRAME_MAX_MS = 0;
const SCALE = Math.min(1, Math.max(0.25, numberParam('scale', 1)));  // ?scale=S: canvas pixels per CSS pixel (software GL's work)

let worker = null;
let state = 'idle';  // opening, running, uploading, stored, refused, error
let firstFrameMs = null;
let pendingStep = null;  // the virtual clock's step under way: {count, ticks}
let steps = 0;
let views = null;
let run = null;  // {assignment, started, tools, held: Set of key codes, keys: Float64Array}
// The fluoroscopy: the case has a unit (the worker says so), the view (made when first shown),
// the lumen it draws the iodine on, the main view shown, the fluoroscopy keys last sent, the
// C-arm panel (js/carm_panel.js).
const fluoro = { available: false, view: null, vessel: null, main: params.get('view') === 'fluoro' ? 'fluoro' : null, bits: 0, panel: null };

function status(text) { document.getElementById('status').textContent = text; }

// The canvas's pixels, the size the worker makes the image for (null: not shown).
function fluoroSize() {
  if (fluoro.main !== 'fluoro') return null;
  const c = document.getElementById('global');  // the canvas fills it (and has no size while hidden)
  const ratio = devicePixelRatio * SCALE;
  return [Math.max(1, Math.round(c.clientWidth * ratio)), Math.max(1, Math.round(c.clientHeight * ratio))];
}

// The main view: the fluoroscopic image or the 3D scene (the button, ?view=, a realistic case).
function showMainView(which) {
  fluoro.main = which;
  const canvas = document.getElementById('fluoro');
  const button = document.getElementById('main-view');
  button.hidden = !fluoro.available;
  if (which === 'fluoro' && fluoro.available && !fluoro.view) {
    try {
      fluoro.view = new FluoroView(canvas, fluoro.vessel.shaders);
      fluoro.view.pixelRatio = devicePixelRatio * SCALE;
      if (fluoro.vessel) fluoro.view.setVessel(fluoro.vessel.vertices, fluoro.vessel.indices);
      if (fluoro.last) fluoro.view.update(fluoro.last);
    } catch (err) {
      document.getElementById('fluoro-note').textContent = err.message;
      fluoro.main = '3d';
    }
  }
  canvas.hidden = fluoro.main !== 'fluoro';
  document.getElementById('carm').hidden = fluoro.main !== 'fluoro' || !fluoro.panel;
  button.textContent = fluoro.main === 'fluoro' ? 'Show the 3D view' : 'Show fluoroscopy';
  if (worker) worker.postMessage({ type: 'fluoro_size', size: fluoroSize() });
  if (views) views.global.dirty = true;
}

// What the monitor shows, under the keys.
function fluoroNote(f) {
  const h = f.header;
  if (!h[H.hasImage]) return 'Fluoroscopy: no image yet (hold Space, the pedal)';
  const what = h[H.subtracted] ? 'subtraction run' : h[H.roadmap] ? 'roadmap over live fluoroscopy' : 'fluoroscopy';
  return `Fluoroscopy: pulse ${h[H.pulse]}, ${what}, image ${h[H.width]} × ${h[H.height]} pixels` +
    (fluoro.view ? `, ${fluoro.view.stats.images} images drawn` : '');
}

// The newest frame the worker wrote into the shared frame (js/frame_share.js), if any: the page's
// animation frame takes it, and so do the worker's ready, advanced and over messages (the state a
// step or the run ended at is shown before the page says so).
let frameReader = null;

function takeFrame() {
  const f = frameReader && run ? frameReader.take() : null;
  if (!f) return false;
  const drive = JSON.parse(f.driveText);
  run.drive.hints = drive.hints;
  if (drive.notes.length) run.drive.note = drive.notes[drive.notes.length - 1];
  if (f.fluoro) takeFluoro(f.fluoro);
  showFrame(f.data, JSON.parse(f.metricsText));
  if (frames) frames.pacer.health(f.lateMs || 0);
  return true;
}

// The fluoroscopy's header and C-arm (each frame), with the phantom or the scenes when new (a
// fluoro_data message); kept whole for a view made later.
function takeFluoro(f) {
  fluoro.last = Object.assign(fluoro.last || {}, f);
  if (fluoro.view) fluoro.view.update(f);
  if (f.carm && fluoro.panel) fluoro.panel.update(f.carm);
}

function showFrame(data, metrics) {
  const s = unpack(data);
  run.last = s;
  run.metrics = metrics;
  if (run.live) run.live.frame(s, metrics);
  s.tools.forEach((t, i) => { const nodes = fit(t.nodes); views.global.setTool(i, nodes); views.local.setTool(i, nodes); });
  views.global.setTip(s.tip);
  views.local.setTip(s.tip);
  views.global.setContacts(s.contacts);
  views.local.setContacts(s.contacts);
  followTip(s);
  document.getElementById('hud').textContent = hudText(s, run, clock === 'virtual');
}

// The local view: behind the tip, along the held tool's last segment.
function followTip(s) {
  const tool = s.tools[s.held];
  if (!tool || tool.nodes.length < 6) return;
  const n = tool.nodes.length / 3;
  const a = tool.nodes.subarray(3 * (n - 2), 3 * (n - 1));
  const b = tool.nodes.subarray(3 * (n - 1), 3 * n);
  const dir = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
  const len = Math.hypot(...dir) || 1;
  const cam = views.local.camera;
  cam.position.set(b[0] - 12 * dir[0] / len + 2, b[1] - 12 * dir[1] / len + 2, b[2] - 12 * dir[2] / len + 2);
  views.local.controls.target.set(b[0], b[1], b[2]);
  cam.near = 0.1;
  cam.updateProjectionMatrix();
}

// The page's drawing, measured over the run (its figures under the keys at the end): the interval
// between frames that drew, and the time the page's thread spends drawing one (WebGL calls issued;
// with a software GL the GPU process's work is not in it).
let frames = null;

function paceFrames(gl) {  // ?fps=, else SOFTWARE_FPS on a software rasteriser (frameCap)
  const cap = frameCap({ fps: params.has('fps') ? numberParam('fps', 0) : null, software: gl.software, softwareFps: SOFTWARE_FPS });
  frames = { interval: new Histogram(), draw: new Histogram(), lastAt: -1, cap, gl,
    pacer: new FramePacer({ minMs: numberParam('frame_ms', cap.minMs), maxMs: numberParam('frame_max_ms', FRAME_MAX_MS) }) };
}

function frameNote() {
  const ms = (h) => `p50 ${(h.percentile(0.5) ?? 0).toFixed(2)} ms, p99 ${(h.percentile(0.99) ?? 0).toFixed(2)} ms`;
  return `Page: ${frames.draw.count} frames drawn, interval ${ms(frames.interval)}; drawing ${ms(frames.draw)}; ` +
    `${frames.pacer.skipped} held back by the frame budget; ${frames.cap.fps ? 'at most ' + frames.cap.fps + ' a second' : 'no cap'} (WebGL: ${frames.gl.name}).`;
}

function draw() {
  if (!views) return;
  const t0 = performance.now();
  if (firstFrameMs !== null && !frames.pacer.due(t0)) return requestAnimationFrame(draw);  // the first frame unpaced
  const took = takeFrame();  // the HUD, the views' tools: only when due (changed text is painted and composited too)
  const fluoroShown = fluoro.main === 'fluoro' && fluoro.view;
  const drew = fluoroShown ? fluoro.view.render() : views.global.render();
  if (fluoroShown && fluoro.last) {  // what the monitor shows, once drawn
    const note = fluoroNote(fluoro.last);
    const line = document.getElementById('fluoro-note');
    if (line.textContent !== note) line.textContent = note;
  }
  const drewLocal = views.local.render();
  if ((took || drewLocal || (drew && !fluoroShown)) && frames) {  // shown (not the fluoroscopy keeping its image)
    const t1 = performance.now();
    frames.draw.add(t1 - t0);
    if (frames.lastAt >= 0) frames.interval.add(t0 - frames.lastAt);
    frames.lastAt = t0;
    frames.pacer.drew(t0);
  }
  if (drew && firstFrameMs === null && run.last) {
    firstFrameMs = performance.now() - run.started;
    document.getElementById('frame-note').textContent = 'First frame ' + firstFrameMs.toFixed(0) + ' ms after choosing the case' +
      (run.openMs !== undefined ? ' (the session opened in ' + run.openMs.toFixed(0) + ' ms).' : '.');
  }
  requestAnimationFrame(draw);
}

function setKeys() {
  run.keys[2] = steering(run.held) ? 1 : 0;
  if (run.boxReport && run.boxReport.live) return;  // the box drives the tool; Tab and Escape still work
  const [insert, twist] = speedsFor(run.held);
  run.keys[0] = insert;
  run.keys[1] = twist;
}

function onKey(e, down) {
  if (!run || state !== 'running' || !isControlKey(e.code)) return;
  e.preventDefault();
  if (down && !e.repeat) {
    if (e.code === 'Tab') worker.postMessage({ type: 'next_tool' });
    else if (e.code === 'Escape') worker.postMessage({ type: 'end' });
    else if (e.code === 'KeyU' || e.code === 'KeyE') worker.postMessage({ type: 'drive', unsheathe: e.code === 'KeyU', retrieve: e.code === 'KeyE' });
    else if (e.code === 'KeyC') { views.global.setVessel(views.mesh); }
    else if (e.code === 'KeyF') {
      for (const v of [views.global, views.local]) { v.vessel.material.wireframe = !v.vessel.material.wireframe; v.dirty = true; }
    }
  }
  if (down) run.held.add(e.code); else run.held.delete(e.code);
  setKeys();
  const bits = fluoroBits(run.held);
  if (bits !== fluoro.bits) {
    fluoro.bits = bits;
    worker.postMessage({ type: 'fluoro_keys', bits });
  }
}
window.addEventListener('keydown', (e) => onKey(e, true));
window.addEventListener('keyup', (e) => onKey(e, false));
window.addEventListener('blur', () => {
  if (!run) return;
  run.held.clear();
  setKeys();
  if (fluoro.bits && worker) worker.postMessage({ type: 'fluoro_keys', bits: (fluoro.bits = 0) });
});
window.addEventListener('resize', () => { if (worker && fluoro.main === 'fluoro') worker.postMessage({ type: 'fluoro_size', size: fluoroSize() }); });

function setState(s, text = s) {
  state = s;
  status(text);
}

function onReady(m) {
  run.openMs = m.open_ms;
  run.tools = m.summary.tools;
  setTarget(m.summary.target);
  fluoro.available = !!m.fluoro;
  if (fluoro.available) {
    fluoro.panel = new CArmPanel(document.getElementById('carm'), (what, values) => worker.postMessage({ type: 'carm', what, values }));
    fluoro.panel.setProjections(m.projections || []);
  }
  if (!fluoro.available) document.getElementById('fluoro-note').textContent = 'This case has no fluoroscopy unit (an analytic tube).';
  showMainView(fluoro.main || (m.summary.realistic ? 'fluoro' : '3d'));
  setState('running');
  document.getElementById('virtual-clock').hidden = clock !== 'virtual';
  const a = run.assignment;
  run.live = new LiveRig({ rig: 'browser-' + user.name.replace(/[^A-Za-z0-9_.-]/g, '-'), caseName: a.case, version: run.version,
    assignment: a.id, toolNames: m.summary.tools, onState: (text) => { document.getElementById('live-note').textContent = text; } });
}

async function onOver(m) {
  if (run.live) {
    if (run.last) run.live.frame(run.last, run.metrics, true);
    run.live.end();
  }
  setState('uploading', 'uploading the record (' + m.record.byteLength + ' bytes)');
  document.getElementById('virtual-clock').hidden = true;
  run.held.clear();
  document.getElementById('draw-note').textContent = frameNote();
  if (m.jitter) {
    const j = m.jitter;
    const ms = (v) => (v === null || v === undefined ? '-' : v.toFixed(3));
    const late = j.late_ticks || {};
    document.getElementById('clock-note').textContent = `Haptic clock: ${j.ticks} ticks, interval p50 ${ms(j.p50_ms)} ms, ` +
      `p99 ${ms(j.p99_ms)} ms, max ${ms(j.max_ms)} ms, ${j.dropped} dropped; lateness p50 ${ms(j.late_p50_ms)} ms, ` +
      `p99 ${ms(j.late_p99_ms)} ms, max ${ms(j.late_max_ms)} ms; a tick's run p50 ${ms(j.tick_p50_ms)} ms, p99 ${ms(j.tick_p99_ms)} ms; ` +
      `late ticks after a sleep ${late.after_sleep ?? '-'}, after ticks ${late.after_ticks ?? '-'}, ` +
      `after the event loop ${late.after_yield ?? '-'}, caught up ${late.catch_up ?? '-'}.`;
  }
  const end = await showEnd({ summary: m.summary, record: m.record, caseName: run.caseName, assignment: run.assignment.id });
  setState(end.state === 'done' ? 'stored' : 'refused', end.state === 'done' ? '' : 'the server refused the record');
}

function startWorker() {
  worker = new Worker('/js/train_worker.js', { name: 'cathbox-haptic' });
  worker.onmessage = (e) => {
    const m = e.data;
    if (m.type === 'frames') frameReader = new FrameReader(m.buffer);
    else if (m.type === 'box') {
      run.boxReport = m.report;
      showBoxReport(m.report);
    }
    else if (m.type === 'fluoro_data') takeFluoro(m);
    else if (m.type === 'box_note') boxNote(m.text);
    else if (m.type === 'carm_note') { if (fluoro.panel) fluoro.panel.refused(m.text); }
    else if (m.type === 'fluoro_vessel') {
      fluoro.vessel = m;
      if (fluoro.view) fluoro.view.setVessel(m.vertices, m.indices);
    }
    else if (m.type === 'ready') { takeFrame(); onReady(m); showBoxReport({ live: false, state: null }); }  // no box in the worker yet: said so
    else if (m.type === 'advanced') { takeFrame(); onStepped(m.ticks); }
    else if (m.type === 'over') { takeFrame(); onOver(m); }
    else if (m.type === 'replayed') onReplayed(m);
    else if (m.type === 'error') { setState('error', ''); showError(m.message); }
  };
  worker.onerror = (e) => { setState('error', ''); showError('worker: ' + e.message); };
}

function setTarget(t) {
  if (!t) return;
  views.global.setTarget(t.slice(0, 3), t[3]);
  views.local.setTarget(t.slice(0, 3), t[3]);
}

// The virtual clock: "Run N ticks" runs exactly N; the note beside it says when they ran.
document.getElementById('main-view').addEventListener('click', (e) => {
  e.currentTarget.blur();  // Space is the pedal, not this button
  showMainView(fluoro.main === 'fluoro' ? '3d' : 'fluoro');
});

document.getElementById('step').addEventListener('click', () => {
  const ticks = Math.round(Number(document.getElementById('step-ticks').value));
  if (!(ticks >= 1) || state !== 'running' || pendingStep) return;
  pendingStep = { count: ++steps, ticks };
  document.getElementById('step-note').textContent = `step ${steps}: running ${ticks} ticks…`;
  worker.postMessage({ type: 'advance', ticks });
});

function onStepped(ticks) {
  if (!pendingStep) return;
  const at = run && run.last ? run.last.tick : 0;
  document.getElementById('step-note').textContent = `step ${pendingStep.count}: ${ticks} ticks run, at tick ${at}`;
  pendingStep = null;
}

async function openCase(a) {
  if (!self.crossOriginIsolated) throw new Error('this page needs cross-origin isolation (the server sends COOP/COEP headers; is a proxy dropping them?)');
  const version = a.case_version === 'latest' ? 'latest' : String(a.case_version);
  const base = '/cases/' + encodeURIComponent(a.case) + '/versions/' + version;
  run = { assignment: a, version, started: performance.now(), caseName: a.case, tools: [], held: new Set(),
    keys: new Float64Array(new SharedArrayBuffer(24)), drive: { hints: [], note: '' } };
  setState('opening', 'opening ' + a.case);
  document.getElementById('pick').hidden = true;
  document.getElementById('run').hidden = false;
  const [bundle, collision, mesh] = await Promise.all([api(base + '/bundle'), api(base + '/mesh?level=collision', { raw: true }), loadMesh(a.case, version)]);
  views = { global: new VesselView(document.getElementById('global')), local: new VesselView(document.getElementById('local')), mesh };
  views.global.setVessel(mesh);
  views.local.setVessel(mesh);
  views.local.tip.scale.setScalar(0.25);  // the tip's marker, not a ball filling the close-up
  paceFrames(glRenderer(views.global.renderer.getContext()));
  if (SCALE !== 1) for (const v of [views.global, views.local]) { v.renderer.setPixelRatio(SCALE); v.resize(); }
  offerBox(params, run, () => worker.postMessage({ type: 'box_hid' }));
  requestAnimationFrame(draw);
  if (!worker) startWorker();
  worker.postMessage({ type: 'open', caseFile: bundle.case_file, caseText: bundle.case, hclmFile: bundle.hclm_file, hclmText: bundle.hclm,
    mesh: collision, clock, keys: run.keys.buffer, box: run.boxUrl, frameMs: frames.cap.workerMs, fluoroSize: fluoro.main === 'fluoro' ? fluoroSize() : null, spinMs: params.has('spin') ? Number(params.get('spin')) : undefined },
    [collision]);
}

// Check a record: the chosen case's collision mesh and the file's bytes to the worker's replay.
function onReplayed(m) {
  const f = m.figures || {};
  document.getElementById('replay-result').textContent = m.passed
    ? `passed: ${f.hashes_checked} state hashes checked over ${f.ticks} of ${f.recorded_ticks} ticks, all match (${m.ms.toFixed(0)} ms)`
    : `FAILED: ${m.message}` + (f.ticks !== undefined ? ` (${f.hashes_checked} hashes checked over ${f.ticks} ticks)` : '');
}

function offerReplay(assignments) {
  const cases = [...new Set(assignments.map((a) => a.case + '\t' + a.case_version))].map((k) => k.split('\t'));
  document.getElementById('replay-case').replaceChildren(...cases.map(([name, version]) =>
    el('option', { value: name + '/' + (version === 'latest' ? 'latest' : version) }, name + (version === 'latest' ? '' : ' v' + version))));
  const input = document.getElementById('replay-file');
  input.addEventListener('change', () => guarded(async () => {
    const file = input.files[0];
    const chosen = document.getElementById('replay-case').value;
    if (!file || !chosen) return;
    document.getElementById('replay-result').textContent = 'replaying ' + file.name + '…';
    const [name, version] = chosen.split('/');
    const [record, mesh] = await Promise.all([file.arrayBuffer(),
      api('/cases/' + encodeURIComponent(name) + '/versions/' + version + '/mesh?level=collision', { raw: true })]);
    if (!worker) startWorker();
    worker.postMessage({ type: 'replay', record, mesh }, [record, mesh]);
  }));
}

if (user) guarded(async () => {
  const { assignments } = await api('/assignments');
  offerReplay(assignments);
  const rows = assignments.map((a) => el('tr', { 'data-id': a.id },
    el('td', {}, a.case + (a.case_version === 'latest' ? '' : ' v' + a.case_version)), el('td', {}, a.note || ''),
    el('td', {}, a.due_at ? a.due_at.slice(0, 10) : '–'),
    el('td', {}, el('button', { class: 'open-case', 'data-id': a.id, onclick: () => guarded(() => openCase(a)) }, 'Run'))));
  document.getElementById('assignments').replaceChildren(rows.length
    ? el('table', {}, el('thead', {}, el('tr', {}, ...['Case', 'Note', 'Due', ''].map((h) => el('th', {}, h)))), el('tbody', {}, ...rows))
    : el('p', { class: 'muted' }, 'No assignment.'));
  document.getElementById('again').addEventListener('click', () => location.reload());
});

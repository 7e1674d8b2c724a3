// Debrief of one run (GET /results/{id}/trace: the server replays the record and samples it):
// the tip path and the tool's shape in 3D at the time of a slider, play/pause/speed, force and
// insertion over time with the events marked, and the metrics against the pass criteria.
import { requireUser, api, guarded, el, fmt, showError } from './api.js';
import { VesselView, parseMesh } from './scene.js';


const EVENT_COLOURS = { wall_contact: '#e65100', wrong_branch: '#c62828', target_reached: '#2e7d32',
  injection: '#6a1b9a', fluoroscopy: '#0277bd', tool_change: '#455a64', flow_arrest: '#00838f' };
const $ = (id) => document.getElementById(id);
const state = { index: 0, playing: false, speed: 1, trace: null, ready: false };
let view = null;
let chart = null;

// Vertical lines on the chart: the events, and the current time.
const marksPlugin = {
  id: 'cathboxMarks',
  afterDatasetsDraw(c) {
    if (!state.trace) return;
    const { ctx, chartArea: a, scales: { x } } = c;
    ctx.save();
    for (const e of state.trace.events) {
      const px = x.getPixelForValue(e.t_ms / 1000);
      ctx.strokeStyle = EVENT_COLOURS[e.kind] || '#000';
      ctx.globalAlpha = 0.5;
      ctx.beginPath(); ctx.moveTo(px, a.top); ctx.lineTo(px, a.bottom); ctx.stroke();
    }
    ctx.globalAlpha = 1;
    ctx.strokeStyle = '#000';
    ctx.lineWidth = 2;
    const px = x.getPixelForValue(state.trace.t_ms[state.index] / 1000);
    ctx.beginPath(); ctx.moveTo(px, a.top); ctx.lineTo(px, a.bottom); ctx.stroke();
    ctx.restore();
  },
};

// eTICI grades travel as their ordinal (host/session/README.md, "Thrombectomy").
const ETICI = ['0', '1', '2a', '2b50', '2b67', '2c', '3'];
const isEtici = (name) => name.startsWith('etici_');
const shown = (name, v) => (isEtici(name) && ETICI[v] !== undefined ? 'eTICI ' + ETICI[v] : fmt(v, 2));

// A thrombectomy run's passes in one row: "1: 2b50 · 2: 3".
function eticiPerPassRow(metrics) {
  const passes = Object.keys(metrics).filter((n) => /^etici_pass_\d+$/.test(n))
    .sort((a, b) => Number(a.slice(11)) - Number(b.slice(11)));
  if (!passes.length) return [];
  const text = passes.map((n) => n.slice(11) + ': ' + (ETICI[metrics[n]] ?? fmt(metrics[n], 0))).join(' · ');
  return [el('tr', { 'data-metric': 'etici_per_pass' }, el('td', {}, 'eTICI per pass'), el('td', { class: 'num', id: 'etici-per-pass' }, text),
    el('td', {}, ''), el('td', {}, ''))];
}

function criteriaTable(result) {
  const ev = result.evaluation;
  const rows = [];
  const judged = new Map((ev ? ev.criteria : []).map((c) => [c.metric, c]));
  // The metrics the criteria judge first, then the rest.
  const names = Object.keys(result.metrics || {}).sort((a, b) => (judged.has(b) ? 1 : 0) - (judged.has(a) ? 1 : 0));
  for (const name of names) {
    const v = result.metrics[name];
    const c = judged.get(name);
    rows.push(el('tr', { 'data-metric': name }, el('td', {}, name.replace(/_/g, ' ')), el('td', { class: 'num' }, shown(name, v)),
      el('td', {}, c ? c.op + ' ' + fmt(c.value, 2) : ''),
      el('td', { class: c ? (c.passed ? 'pass' : 'fail') : '' }, c ? (c.passed ? 'pass' : 'fail') : '')));
  }
  const verdict = result.complete === false ? el('p', { class: 'fail', id: 'verdict' }, 'Cut record: ' + result.cut)
    : result.passed === null ? el('p', { class: 'muted' }, 'Not under an assignment: no pass criteria.')
    : el('p', { class: result.passed ? 'pass' : 'fail', id: 'verdict' }, result.passed ? 'Passed' : 'Not passed');
  return [verdict, el('table', {}, el('thead', {}, el('tr', {}, ...['Metric', 'Measured', 'Criterion', ''].map((h) => el('th', {}, h)))),
    el('tbody', {}, ...eticiPerPassRow(result.metrics || {}), ...rows))];
}

function seek(i) {
  const tr = state.trace;
  state.index = Math.max(0, Math.min(tr.samples - 1, i));
  const k = state.index;
  $('slider').value = String(k);
  const tip = tr.tip_mm.slice(3 * k, 3 * k + 3);
  view.setTool(0, tr.nodes_mm[k]);
  view.setTip(tip);
  $('clock').textContent = fmt(tr.t_ms[k] / 1000, 1) + ' / ' + fmt(tr.t_ms[tr.samples - 1] / 1000, 1) + ' s';
  $('now').replaceChildren(
    el('div', {}, 'tip ', el('b', { id: 'now-tip' }, tip.map((v) => v.toFixed(1)).join(', '))),
    el('div', {}, 'insertion ', el('b', {}, fmt(tr.insertion_mm[k]) + ' mm')),
    el('div', {}, 'rotation ', el('b', {}, fmt(tr.rotation_deg[k]) + '°')),
    el('div', {}, 'hand ', el('b', {}, fmt(tr.hand_mN[k]) + ' mN')),
    el('div', {}, 'wall ', el('b', {}, fmt(tr.wall_peak_mN[k]) + ' mN')),
    el('div', {}, 'fluoro ', tr.fluoro[k] ? el('span', { class: 'fluoro-on' }, 'ON') : el('b', {}, 'off')));
  if (chart) {
    // The plot's window follows the cursor when it shows less than the whole run.
    const span = Number($('window').value);
    const now = tr.t_ms[k] / 1000;
    const end = tr.t_ms[tr.samples - 1] / 1000;
    const min = span ? Math.max(0, Math.min(now - span / 2, end - span)) : undefined;
    const max = span ? min + span : undefined;
    if (chart.options.scales.x.min !== min || chart.options.scales.x.max !== max) {
      chart.options.scales.x.min = min;
      chart.options.scales.x.max = max;
      chart.update('none');
    } else {
      chart.draw();
    }
  }
}

function drawChart(tr) {
  const t = tr.t_ms.map((v) => v / 1000);
  const series = (ys) => ys.map((y, i) => ({ x: t[i], y }));
  // eslint-disable-next-line no-undef
  chart = new Chart($('chart'), {
    type: 'line',
    data: {
      datasets: [
        { label: 'hand force mN', data: series(tr.hand_mN), borderColor: '#1f6feb', yAxisID: 'f' },
        { label: 'wall force mN (peak)', data: series(tr.wall_peak_mN), borderColor: '#e65100', yAxisID: 'f' },
        { label: 'insertion mm', data: series(tr.insertion_mm), borderColor: '#2e7d32', yAxisID: 'mm' },
      ],
    },
    options: {
      animation: false, maintainAspectRatio: false, parsing: false, normalized: true,
      elements: { point: { radius: 0 }, line: { borderWidth: 1.5 } },
      interaction: { mode: 'nearest', axis: 'x', intersect: false },
      onClick: (e, items, c) => { const x = c.scales.x.getValueForPixel(e.x); seekTime(x * 1000); },
      plugins: { decimation: { enabled: true, algorithm: 'lttb', samples: 1000 } },
      scales: { x: { type: 'linear', title: { display: true, text: 's' } },
                f: { position: 'left', title: { display: true, text: 'mN' } },
                mm: { position: 'right', title: { display: true, text: 'mm' }, grid: { drawOnChartArea: false } } },
    },
    plugins: [marksPlugin],
  });
}

function seekTime(ms) {
  const tr = state.trace;
  let lo = 0; let hi = tr.samples - 1;
  while (lo < hi) { const mid = (lo + hi) >> 1; if (tr.t_ms[mid] < ms) lo = mid + 1; else hi = mid; }
  seek(lo);
}

function drawMarks(tr) {
  const end = tr.t_ms[tr.samples - 1] || 1;
  $('marks').replaceChildren(...tr.events.map((e) => el('span', { title: e.kind + ' at ' + fmt(e.t_ms / 1000, 2) + ' s', 'data-kind': e.kind,
    style: 'left:' + (100 * e.t_ms / end).toFixed(3) + '%;background:' + (EVENT_COLOURS[e.kind] || '#000') })));
  const counts = {};
  for (const e of tr.events) counts[e.kind] = (counts[e.kind] || 0) + 1;
  $('legend').replaceChildren(...Object.entries(EVENT_COLOURS).filter(([k]) => counts[k]).map(([k, c]) =>
    el('span', {}, el('i', { style: 'background:' + c }), k.replace(/_/g, ' ') + ' ×' + counts[k])));
}

let last = null;
let carry = 0;
function loop(now) {
  if (state.playing && state.trace) {
    const tr = state.trace;
    if (last !== null) {
      carry += (now - last) * state.speed;
      const target = tr.t_ms[state.index] + carry;
      let k = state.index;
      while (k + 1 < tr.samples && tr.t_ms[k + 1] <= target) k++;
      if (k !== state.index) { carry = target - tr.t_ms[k]; seek(k); }
      if (k >= tr.samples - 1) { state.playing = false; $('play').textContent = 'Play'; }
    }
    last = now;
  } else {
    last = null;
    carry = 0;
  }
  if (view) view.render();
  requestAnimationFrame(loop);
}

if (requireUser()) guarded(async () => {
  const id = new URLSearchParams(location.search).get('id');
  if (!id) throw new Error('no result given (debrief.html?id=N)');
  const data = await api('/results/' + encodeURIComponent(id) + '/trace');
  const tr = data.trace;
  const r = data.result;
  state.trace = tr;
  state.result = r;
  $('title').textContent = 'Debrief of run ' + r.id + ': ' + r.trainee + ', ' + r.case + ', ' + (r.started_at || '').slice(0, 16).replace('T', ' ');
  view = new VesselView($('view3d'));
  if (data.mesh_url) {
    const buffer = await api(data.mesh_url.replace(/^\/api\/v1/, ''), { raw: true });
    view.setVessel(parseMesh(buffer));
  }
  view.setTarget(tr.target_mm, tr.target_radius_mm);
  view.addPath(tr.tip_mm);
  $('slider').max = String(Math.max(0, tr.samples - 1));
  $('slider').addEventListener('input', () => seek(Number($('slider').value)));
  $('play').addEventListener('click', () => {
    if (state.index >= tr.samples - 1) seek(0);
    state.playing = !state.playing;
    $('play').textContent = state.playing ? 'Pause' : 'Play';
  });
  $('speed').addEventListener('change', () => { state.speed = Number($('speed').value); });
  $('window').addEventListener('change', () => seek(state.index));
  // A long run opens on a minute around the cursor: the whole of it is a blur of events.
  if (tr.t_ms[tr.samples - 1] > 10 * 60 * 1000) $('window').value = '60';
  $('criteria').replaceChildren(...criteriaTable(r));
  drawChart(tr);
  drawMarks(tr);
  seek(0);
  view.render();
  state.ready = true;
}).then(() => { if (!state.ready) showError(document.getElementById('error').textContent || 'debrief failed'); });

requestAnimationFrame(loop);

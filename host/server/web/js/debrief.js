// Debrief of one run (GET /results/{id}/trace: the server replays the record and samples it):
// the tip path and the tool's shape in 3D at the time of a slider, play/pause/speed, force and
// insertion over time with the events marked (a thrombectomy's passes with their eTICI, its
// emboli, and the stent's retrieval force with its peak), and the metrics against the pass criteria.
import { requireUser, api, guarded, el, fmt, showError } from './api.js';
import { VesselView, parseMesh } from './scene.js';


const EVENT_COLOURS = { wall_contact: '#e65100', wrong_branch: '#c62828', target_reached: '#2e7d32',
  injection: '#6a1b9a', fluoroscopy: '#0277bd', tool_change: '#455a64', flow_arrest: '#00838f',
  pass: '#ad1457', embolus: '#5d4037' };
const RETRIEVAL_COLOUR = '#ad1457';
const $ = (id) => document.getElementById(id);
const state = { index: 0, playing: false, speed: 1, trace: null, ready: false };
let view = null;
let chart = null;

// What a mark says: "pass 1: eTICI 2b67", "embolus 1 (M2, new territory)", or its kind.
function eventText(e) {
  if (e.kind === 'pass') return 'pass ' + e.pass + (e.etici !== undefined ? ': eTICI ' + e.etici : '');
  if (e.kind === 'embolus') {
    const where = [e.segment, e.new_territory ? 'new territory' : ''].filter(Boolean).join(', ');
    return 'embolus ' + e.embolus + (where ? ' (' + where + ')' : '');
  }
  return e.kind.replace(/_/g, ' ');
}
// The label over a thrombectomy mark on the plot: "P1 3", "E1".
const markLabel = (e) => (e.kind === 'pass' ? 'P' + e.pass + (e.etici !== undefined ? ' ' + e.etici : '')
  : e.kind === 'embolus' ? 'E' + e.embolus : null);

// The retrieval force's peak: its sample and value (null when no stent was pulled).
function retrievalPeak(tr) {
  if (!tr.retrieval_mN) return null;
  let k = 0;
  for (let i = 1; i < tr.retrieval_mN.length; i++) if (tr.retrieval_mN[i] > tr.retrieval_mN[k]) k = i;
  return tr.retrieval_mN[k] > 0 ? { k, mN: tr.retrieval_mN[k] } : null;
}

function drawPeak(c, tr) {
  const peak = retrievalPeak(tr);
  if (!peak) return;
  const { ctx, scales: { x, f } } = c;
  const px = x.getPixelForValue(tr.t_ms[peak.k] / 1000);
  const py = f.getPixelForValue(peak.mN);
  ctx.fillStyle = RETRIEVAL_COLOUR;
  ctx.beginPath(); ctx.arc(px, py, 3.5, 0, 2 * Math.PI); ctx.fill();
  ctx.font = '11px sans-serif';
  ctx.textAlign = px > (c.chartArea.left + c.chartArea.right) / 2 ? 'right' : 'left';
  ctx.fillText('retrieval peak ' + fmt(peak.mN / 1000, 3) + ' N', px + (ctx.textAlign === 'left' ? 6 : -6), Math.max(py, c.chartArea.top + 10));
}

// Vertical lines on the chart: the events (a thrombectomy's passes and emboli labelled), the
// retrieval force's peak, and the current time.
const marksPlugin = {
  id: 'cathboxMarks',
  afterDatasetsDraw(c) {
    if (!state.trace) return;
    const { ctx, chartArea: a, scales: { x } } = c;
    ctx.save();
    ctx.font = '11px sans-serif';
    ctx.textAlign = 'left';
    for (const e of state.trace.events) {
      const px = x.getPixelForValue(e.t_ms / 1000);
      const label = markLabel(e);
      ctx.strokeStyle = EVENT_COLOURS[e.kind] || '#000';
      ctx.globalAlpha = label ? 0.9 : 0.5;
      ctx.lineWidth = label ? 2 : 1;
      ctx.beginPath(); ctx.moveTo(px, a.top); ctx.lineTo(px, a.bottom); ctx.stroke();
      if (label && px >= a.left && px <= a.right) {
        ctx.fillStyle = EVENT_COLOURS[e.kind];
        ctx.fillText(label, px + 3, a.top + (e.kind === 'pass' ? 10 : 22));
      }
    }
    ctx.globalAlpha = 1;
    drawPeak(c, state.trace);
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
    ...(tr.retrieval_mN ? [el('div', {}, 'retrieval ', el('b', {}, fmt(tr.retrieval_mN[k]) + ' mN'))] : []),
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

// A thrombectomy's retrieval force (the pull on a stent's push wire while it is retrieved): its
// label gives the peak, or says there was none (an aspiration pass pulls no stent).
function retrievalSeries(tr, series) {
  if (!tr.retrieval_mN) return [];
  const peak = retrievalPeak(tr);
  const label = 'retrieval force mN (' + (peak ? 'peak ' + fmt(peak.mN / 1000, 3) + ' N' : 'no stent pulled') + ')';
  return [{ label, data: series(tr.retrieval_mN), borderColor: RETRIEVAL_COLOUR, borderDash: [4, 2], yAxisID: 'f' }];
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
        ...retrievalSeries(tr, series),
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
  $('marks').replaceChildren(...tr.events.map((e) => el('span', { title: eventText(e) + ' at ' + fmt(e.t_ms / 1000, 2) + ' s', 'data-kind': e.kind,
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

// The table of runs (filters, sorting, CSV) and the learning curves (each metric over a
// trainee's attempts, Chart.js from Debian's libjs-chart.js as the global `Chart`), shared by the
// instructor's results page and the trainee's own page.
import { api, el, fmt, escapeHtml } from './api.js';

export const CURVE_METRICS = ['procedure_time_s', 'tip_path_mm', 'peak_wall_force_mN', 'wall_contacts', 'closest_to_target_mm', 'time_above_threshold_s'];

// Every result matching `filters` ({trainee, case, since, until, passed}), newest first.
export async function fetchResults(filters = {}) {
  const q = new URLSearchParams();
  for (const [k, v] of Object.entries(filters)) if (v !== undefined && v !== null && v !== '') q.set(k, v);
  const out = [];
  for (let offset = 0; offset < 20000; offset += 1000) {
    q.set('limit', '1000');
    q.set('offset', String(offset));
    const page = await api('/results?' + q.toString());
    out.push(...page.results);
    if (page.results.length < 1000) break;
  }
  return out;
}

const COLUMNS = [
  { key: 'id', label: '#', num: true },
  { key: 'trainee', label: 'Trainee' },
  { key: 'case', label: 'Case' },
  { key: 'started_at', label: 'Started', get: (r) => (r.started_at || '').slice(0, 16).replace('T', ' ') },
  { key: 'duration_s', label: 'Duration s', num: true },
  // A cut record (no end block) is for debriefs only: never graded, and says so.
  { key: 'passed', label: 'Pass', get: (r) => (r.complete === false ? 'cut' : r.passed === null ? '–' : r.passed ? 'pass' : 'fail') },
  { key: 'm.tip_path_mm', label: 'Tip path mm', num: true },
  { key: 'm.peak_wall_force_mN', label: 'Peak wall mN', num: true },
  { key: 'm.wall_contacts', label: 'Contacts', num: true },
  { key: 'm.target_reached', label: 'Target', num: true },
];

function value(r, key) {
  if (key.startsWith('m.')) return r.metrics ? r.metrics[key.slice(2)] : undefined;
  return r[key];
}

export class ResultsTable {
  constructor(container, { showTrainee = true } = {}) {
    this.container = container;
    this.columns = COLUMNS.filter((c) => showTrainee || c.key !== 'trainee');
    this.sort = { key: 'id', dir: -1 };
    this.rows = [];
  }

  set(rows) { this.rows = rows; this.draw(); }

  sorted() {
    const { key, dir } = this.sort;
    return [...this.rows].sort((a, b) => {
      const x = value(a, key); const y = value(b, key);
      if (x === y) return 0;
      if (x === undefined || x === null) return 1;
      if (y === undefined || y === null) return -1;
      return (x < y ? -1 : 1) * dir;
    });
  }

  draw() {
    const head = el('tr', {}, ...this.columns.map((c) => {
      const th = el('th', { 'data-key': c.key }, c.label);
      if (this.sort.key === c.key) th.className = this.sort.dir > 0 ? 'sorted-asc' : 'sorted-desc';
      th.onclick = () => {
        this.sort = { key: c.key, dir: this.sort.key === c.key ? -this.sort.dir : (c.num ? -1 : 1) };
        this.draw();
      };
      return th;
    }), el('th', {}, ''));
    const body = this.sorted().map((r) => el('tr', { 'data-id': r.id }, ...this.columns.map((c) => {
      const v = c.get ? c.get(r) : value(r, c.key);
      const td = el('td', { class: c.num ? 'num' : '' }, c.num ? fmt(v, 1) : (v ?? '–'));
      if (c.key === 'passed' && r.passed !== null) td.className = r.passed ? 'pass' : 'fail';
      return td;
    }), el('td', {}, el('a', { href: '/debrief.html?id=' + r.id }, 'debrief'))));
    const table = el('table', { id: 'results-table' }, el('thead', {}, head), el('tbody', {}, ...body));
    this.container.replaceChildren(body.length ? table : el('p', { class: 'muted' }, 'No result matches.'));
  }

  // Every column and every metric, as the table is sorted.
  csv() {
    const metrics = [...new Set(this.rows.flatMap((r) => Object.keys(r.metrics || {})))].sort();
    const fields = ['id', 'trainee', 'case', 'assignment', 'started_at', 'uploaded_at', 'duration_s', 'passed', 'complete'];
    const quote = (v) => {
      const s = v === null || v === undefined ? '' : String(v);
      return /[",\n]/.test(s) ? '"' + s.replace(/"/g, '""') + '"' : s;
    };
    const lines = [fields.concat(metrics).join(',')];
    for (const r of this.sorted()) lines.push(fields.map((f) => quote(r[f])).concat(metrics.map((m) => quote(r.metrics ? r.metrics[m] : ''))).join(','));
    return lines.join('\n') + '\n';
  }
}

export function download(name, text, type = 'text/csv') {
  const a = el('a', { href: URL.createObjectURL(new Blob([text], { type })), download: name });
  document.body.append(a);
  a.click();
  a.remove();
}

const charts = [];  // the curves drawn, destroyed before the next ones

// One small chart per metric: its value at each attempt (oldest first), passes in green.
export function drawCurves(container, results, metrics = CURVE_METRICS) {
  for (const c of charts.splice(0)) c.destroy();
  container.innerHTML = '';
  const attempts = [...results].sort((a, b) => (a.started_at < b.started_at ? -1 : a.started_at > b.started_at ? 1 : a.id - b.id));
  if (!attempts.length) { container.append(el('p', { class: 'muted' }, 'No attempt yet.')); return; }
  for (const metric of metrics) {
    const points = attempts.map((r, i) => ({ x: i + 1, y: r.metrics ? r.metrics[metric] : undefined, r })).filter((p) => p.y !== undefined);
    if (!points.length) continue;
    const canvas = el('canvas', { 'data-metric': metric });
    container.append(el('div', { class: 'card' }, el('h2', {}, metric.replace(/_/g, ' ')), el('div', { class: 'chart-box' }, canvas)));
    // eslint-disable-next-line no-undef
    const chart = new Chart(canvas, {
      type: 'line',
      data: {
        datasets: [{
          label: metric,
          data: points.map((p) => ({ x: p.x, y: p.y })),
          borderColor: '#1f6feb',
          pointBackgroundColor: points.map((p) => (p.r.passed === null ? '#1f6feb' : p.r.passed ? '#2e7d32' : '#c62828')),
          pointRadius: 4,
          tension: 0,
        }],
      },
      options: {
        animation: false,
        maintainAspectRatio: false,
        parsing: false,
        scales: { x: { type: 'linear', title: { display: true, text: 'attempt' }, ticks: { stepSize: 1, precision: 0 } },
                  y: { title: { display: true, text: metric } } },
        plugins: { legend: { display: false } },
      },
    });
    charts.push(chart);
  }
}

export function caseOptions(select, cases) {
  select.replaceChildren(el('option', { value: '' }, 'any'), ...cases.map((c) => el('option', { value: c.name }, c.name)));
}

export { escapeHtml };

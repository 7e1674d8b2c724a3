// The trainee page's end of run: the metrics (against the assignment's criteria once the
// server has them), the record offered for download whatever happens next, and the upload as
// cathbox-trainer uploads it (POST /results?assignment=ID; the server replays it with every
// state hash before it files it).
import { api, showError, el, fmt } from './api.js';

function showMetrics(summary, result) {
  const evaluation = new Map(((result && result.evaluation && result.evaluation.criteria) || []).map((c) => [c.metric, c]));
  const rows = Object.entries(summary.metrics).map(([name, value]) => {
    const c = evaluation.get(name);
    return el('tr', {}, el('td', {}, name), el('td', { class: 'num' }, fmt(value, 2)),
      el('td', { class: c ? (c.passed ? 'pass' : 'fail') : 'muted' }, c ? c.op + ' ' + fmt(c.value, 1) : ''));
  });
  document.getElementById('metrics').replaceChildren(el('table', { id: 'metrics-table' },
    el('thead', {}, el('tr', {}, el('th', {}, 'Metric'), el('th', {}, 'Value'), el('th', {}, 'Criterion'))), el('tbody', {}, ...rows)));
}

// {state: 'done' | 'refused', result, error}.
export async function showEnd({ summary, record, caseName, assignment }) {
  document.getElementById('end').hidden = false;
  document.getElementById('end-title').textContent = 'End of run: ' + summary.end + ' (' + (summary.ticks / 1000).toFixed(1) + ' s)';
  showMetrics(summary, null);
  const name = caseName + '-' + new Date().toISOString().replace(/[:.]/g, '-') + '.cbxrec';
  const blob = new Blob([record], { type: 'application/octet-stream' });
  document.getElementById('record-link').replaceChildren(el('a', { id: 'record-download', download: name,
    href: URL.createObjectURL(blob) }, 'Download the record (' + record.byteLength + ' bytes)'));
  const line = document.getElementById('upload');
  line.textContent = 'Uploading the record…';
  try {
    const stored = await api('/results?assignment=' + assignment, { method: 'POST', bytes: record });
    const result = await api('/results/' + stored.id);  // with its evaluation against the criteria
    showMetrics(summary, result);
    line.replaceChildren('Uploaded and checked by the server: ', result.passed === true ? el('b', { class: 'pass' }, 'passed')
      : el('b', { class: 'fail' }, result.complete === false ? 'cut run' : 'not passed'), ' — ', el('a', { href: '/debrief.html?id=' + result.id }, 'debrief'));
    return { state: 'done', result };
  } catch (err) {
    line.textContent = 'The server refused the record: ' + err.message;
    showError(err.message);
    return { state: 'refused', error: err.message };
  }
}

// Instructor results: the table of runs with filters and sorting, CSV export, and for one
// trainee each metric over their attempts.
import { requireUser, api, guarded, el } from './api.js';
import { ResultsTable, fetchResults, drawCurves, download, caseOptions } from './results_table.js';

const table = new ResultsTable(document.getElementById('table'));
const $ = (id) => document.getElementById(id);

function filters() {
  return { trainee: $('f-trainee').value, case: $('f-case').value, since: $('f-since').value,
           until: $('f-until').value, passed: $('f-passed').value };
}

async function refresh() {
  await guarded(async () => {
    const f = filters();
    const rows = await fetchResults(f);
    table.set(rows);
    $('count').textContent = rows.length + ' run' + (rows.length === 1 ? '' : 's');
    const url = new URL(location.href);
    for (const [k, v] of Object.entries(f)) { if (v) url.searchParams.set(k, v); else url.searchParams.delete(k); }
    history.replaceState(null, '', url);
    if (f.trainee) {
      $('curves-title').textContent = 'Learning curves of ' + f.trainee + (f.case ? ' on ' + f.case : '');
      drawCurves($('curves'), rows);
    } else {
      $('curves-title').replaceChildren('Learning curves ', el('span', { class: 'muted' }, '(pick a trainee)'));
      drawCurves($('curves'), [], []);
      $('curves').innerHTML = '';
    }
  });
}

async function start() {
  await guarded(async () => {
    const [users, cases] = await Promise.all([api('/users'), api('/cases')]);
    $('f-trainee').replaceChildren(el('option', { value: '' }, 'any'),
      ...users.users.filter((u) => u.role === 'trainee').map((u) => el('option', { value: u.name }, u.name)));
    caseOptions($('f-case'), cases.cases);
    const q = new URLSearchParams(location.search);
    for (const k of ['trainee', 'case', 'since', 'until', 'passed']) if (q.get(k)) $('f-' + k).value = q.get(k);
  });
  $('filters').addEventListener('submit', (e) => { e.preventDefault(); refresh(); });
  $('f-trainee').addEventListener('change', refresh);
  $('csv').addEventListener('click', () => download('cathbox-results.csv', table.csv()));
  await refresh();
}

if (requireUser(['instructor', 'admin'])) start();

// A trainee's own page: assignments (with their criteria and results), results, learning curves.
import { requireUser, api, guarded, el, fmt } from './api.js';
import { ResultsTable, fetchResults, drawCurves } from './results_table.js';

const user = requireUser(['trainee']);

function criteriaText(criteria) {
  return (criteria || []).map((c) => c.metric + ' ' + c.op + ' ' + fmt(c.value, 1)).join('; ') || 'none';
}

if (user) guarded(async () => {
  const [assignments, results] = await Promise.all([api('/assignments'), fetchResults({ trainee: user.name })]);
  const rows = assignments.assignments.map((a) => {
    const mine = results.filter((r) => r.assignment === a.id);
    const passed = mine.some((r) => r.passed);
    return el('tr', { 'data-id': a.id }, el('td', {}, a.case + (a.case_version === 'latest' ? '' : ' v' + a.case_version)),
      el('td', {}, a.note || ''), el('td', {}, criteriaText(a.criteria)), el('td', {}, a.due_at ? a.due_at.slice(0, 10) : '–'),
      el('td', { class: mine.length ? (passed ? 'pass' : 'fail') : 'muted' }, mine.length ? (passed ? 'passed' : 'not yet') + ' (' + mine.length + ' run' + (mine.length === 1 ? '' : 's') + ')' : 'not started'));
  });
  document.getElementById('assignments').replaceChildren(rows.length
    ? el('table', {}, el('thead', {}, el('tr', {}, ...['Case', 'Note', 'Pass criteria', 'Due', 'Status'].map((h) => el('th', {}, h)))), el('tbody', {}, ...rows))
    : el('p', { class: 'muted' }, 'No assignment.'));
  new ResultsTable(document.getElementById('table'), { showTrainee: false }).set(results);
  drawCurves(document.getElementById('curves'), results);
});

// Admin: accounts and roles (POST/PATCH /users), case upload (POST /cases: the validator's
// file:line line shown as the server wrote it).
import { requireUser, api, guarded, el, showError } from './api.js';

const $ = (id) => document.getElementById(id);

async function drawUsers() {
  const { users } = await api('/users');
  const rows = users.map((u) => {
    const role = el('select', { 'data-user': u.name }, ...['trainee', 'instructor', 'admin'].map((r) => el('option', r === u.role ? { selected: '' } : {}, r)));
    role.onchange = () => guarded(async () => { await api('/users/' + encodeURIComponent(u.name), { method: 'PATCH', body: { role: role.value } }); await drawUsers(); });
    const toggle = el('button', { class: 'plain' }, u.disabled ? 'Enable' : 'Disable');
    toggle.onclick = () => guarded(async () => { await api('/users/' + encodeURIComponent(u.name), { method: 'PATCH', body: { disabled: !u.disabled } }); await drawUsers(); });
    return el('tr', {}, el('td', {}, u.name), el('td', {}, role), el('td', {}, u.disabled ? 'disabled' : 'active'), el('td', {}, u.created_at.slice(0, 10)), el('td', {}, toggle));
  });
  $('users').replaceChildren(el('table', {}, el('thead', {}, el('tr', {}, ...['Name', 'Role', 'State', 'Created', ''].map((h) => el('th', {}, h)))), el('tbody', {}, ...rows)));
}

async function drawCases() {
  const { cases } = await api('/cases');
  $('cases').replaceChildren(cases.length ? el('table', {}, el('thead', {}, el('tr', {}, ...['Name', 'Version', 'Title', 'Files', 'Mesh triangles', 'Uploaded'].map((h) => el('th', {}, h)))),
    el('tbody', {}, ...cases.map((c) => el('tr', {}, el('td', {}, c.name), el('td', {}, c.version), el('td', {}, c.title), el('td', {}, c.case_file + (c.hclm_file ? ', ' + c.hclm_file : '')),
      el('td', { class: 'num' }, c.sizes.mesh_triangles), el('td', {}, c.created_at.slice(0, 10))))))
    : el('p', { class: 'muted' }, 'No case yet.'));
}

function start() {
$('new-user').addEventListener('submit', (e) => {
  e.preventDefault();
  guarded(async () => {
    await api('/users', { method: 'POST', body: { name: $('u-name').value, role: $('u-role').value, password: $('u-password').value } });
    $('new-user').reset();
    await drawUsers();
  });
});

// The bytes as lowercase hex, as POST /cases takes a surface (surface_hex).
function hexOf(bytes) {
  const digits = new Array(bytes.length);
  for (let i = 0; i < bytes.length; ++i) digits[i] = bytes[i].toString(16).padStart(2, '0');
  return digits.join('');
}

$('upload').addEventListener('submit', (e) => {
  e.preventDefault();
  guarded(async () => {
    const caseFile = $('c-case').files[0];
    const hclmFile = $('c-hclm').files[0];
    const body = { name: $('c-name').value, case_file: caseFile.name, case: await caseFile.text() };
    if (hclmFile) { body.hclm_file = hclmFile.name; body.hclm = await hclmFile.text(); }
    const surfaceFile = $('c-surface').files[0];
    if (surfaceFile) { body.surface_file = surfaceFile.name; body.surface_hex = hexOf(new Uint8Array(await surfaceFile.arrayBuffer())); }
    const r = await api('/cases', { method: 'POST', body });
    $('upload-result').textContent = r.created ? 'stored as ' + r.name + ' version ' + r.version : 'unchanged: ' + r.name + ' version ' + r.version + ' has these files';
    await drawCases();
  }).then(() => { if (!$('error').hidden) $('upload-result').textContent = ''; });
});

guarded(async () => { await Promise.all([drawUsers(), drawCases()]); });
}

if (requireUser(['admin'])) start();
export { showError };

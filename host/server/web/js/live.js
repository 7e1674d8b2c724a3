// Instructor live view: the watcher WebSocket (/api/v1/live/watch), one panel per rig watched
// (the vessel in 3D, the tools, tip, contacts coloured by force, fluoroscopy, metrics), drawn
// with requestAnimationFrame from the newest frame of each rig.
import { requireUser, token, showError, el, fmt } from './api.js';
import { VesselView, loadMesh } from './scene.js';


const rigs = new Map();     // rig name -> the rig as the server describes it
const panels = new Map();   // rig name -> {view, stats, frame, drawn, ...}
// How the view keeps up, shown under the title: animation frames drawn a second and stream
// frames drawn a second (all panels). Each panel shows its last frame's seq and how many of its
// frames it drew (only the newest is drawn when several arrive between two animation frames).
let socket = null;
let wanted = '';  // the rigs the address names

const SHOWN_METRICS = ['procedure_time_s', 'tip_path_mm', 'wall_contacts', 'peak_wall_force_mN', 'wrong_branch_entries', 'target_reached'];

function connect() {
  const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
  wanted = new URLSearchParams(location.search).get('rigs') || '';
  // The token goes as a subprotocol (a header), never in the URL where logs would keep it.
  socket = new WebSocket(proto + '//' + location.host + '/api/v1/live/watch?rigs=' + encodeURIComponent(wanted),
    ['cathbox', 'bearer.' + token()]);
  socket.onopen = () => { document.getElementById('status').textContent = '(connected)'; };
  socket.onclose = () => {
    document.getElementById('status').textContent = '(disconnected; retrying)';
    setTimeout(connect, 2000);
  };
  socket.onmessage = (e) => {
    const m = JSON.parse(e.data);
    if (m.type === 'rigs') {
      rigs.clear();
      for (const r of m.rigs) rigs.set(r.rig, r);
      for (const name of wanted.split(',').filter(Boolean)) if (rigs.has(name)) openPanel(name);
      drawRigs();
    } else if (m.type === 'started') {
      rigs.set(m.rig.rig, m.rig);
      // A rig named in the address (live.html?rigs=a,b) opens as soon as it starts.
      if (wanted.split(',').includes(m.rig.rig) && !panels.has(m.rig.rig)) openPanel(m.rig.rig);
      else if (panels.has(m.rig.rig)) panels.get(m.rig.rig).title.textContent = m.rig.rig + ' — ' + m.rig.user + ', ' + m.rig.case;
      drawRigs();
    } else if (m.type === 'ended') {
      const was = rigs.get(m.rig);
      rigs.delete(m.rig);
      const p = panels.get(m.rig);
      if (p) p.title.textContent = m.rig + (was ? ' — ' + was.user + ', ' + was.case : '') + ' (ended)';
      drawRigs();
    } else if (m.type === 'frame') {
      const p = panels.get(m.rig);
      if (p) p.frame = m.frame;
    } else if (m.type === 'error') {
      showError(m.error);
    }
  };
}

function drawRigs() {
  const box = document.getElementById('rigs');
  box.innerHTML = '';
  if (rigs.size === 0) box.append(el('span', { class: 'muted', id: 'no-rigs' }, 'No rig is in session.'));
  for (const r of [...rigs.values()].sort((a, b) => a.rig.localeCompare(b.rig))) {
    const b = el('button', { class: 'rig-chip' + (panels.has(r.rig) ? ' watching' : ''), 'data-rig': r.rig,
      title: 'case ' + r.case + ', since ' + r.started_at },
      r.rig + ' · ' + r.user + ' · ' + r.case);
    b.onclick = () => (panels.has(r.rig) ? closePanel(r.rig) : openPanel(r.rig));
    box.append(b);
  }
}

function sendWatch() {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify({ type: 'watch', rigs: [...panels.keys()] }));
  const url = new URL(location.href);
  if (panels.size) url.searchParams.set('rigs', [...panels.keys()].join(','));
  else url.searchParams.delete('rigs');
  history.replaceState(null, '', url);
}

function openPanel(name) {
  if (panels.has(name)) return;
  const rig = rigs.get(name);
  const title = el('span', {}, name + (rig ? ' — ' + rig.user + ', ' + rig.case : ''));
  const close = el('button', { class: 'plain' }, 'Close');
  const view3d = el('div', { class: 'view3d' });
  const statBox = el('div', { class: 'stats' });
  const panel = el('section', { class: 'panel', 'data-rig': name }, el('header', {}, title, close), view3d, statBox);
  document.getElementById('panels').append(panel);
  const p = { name, panel, title, view: new VesselView(view3d), stats: statBox, frame: null, shown: null, fluoroTime: null, drawn: 0 };
  close.onclick = () => closePanel(name);
  panels.set(name, p);
  if (rig) {
    loadMesh(rig.case, rig.case_version || 'latest').then((mesh) => p.view.setVessel(mesh)).catch((e) => showError(e.message));
  }
  sendWatch();
  drawRigs();
}

function closePanel(name) {
  const p = panels.get(name);
  if (!p) return;
  p.view.dispose();
  p.panel.remove();
  panels.delete(name);
  sendWatch();
  drawRigs();
}

function stat(label, value, id) {
  return el('div', {}, label + ' ', el('b', id ? { 'data-stat': id } : {}, value));
}

// The newest frame into the scene and the numbers (once per frame received).
function apply(p) {
  const f = p.frame;
  p.shown = f;
  (f.tools || []).forEach((t, i) => p.view.setTool(i, t.nodes_mm || []));
  p.view.setTip(f.tip_mm);
  p.view.setContacts(f.contacts || []);
  p.drawn++;
  const fluoroTime = f.fluoro ? f.fluoro.time_s : null;
  const fluoroOn = f.fluoro && (f.fluoro.on || (p.fluoroTime !== null && fluoroTime > p.fluoroTime));
  p.fluoroTime = fluoroTime;
  const forces = f.forces || {};
  const m = f.metrics || {};
  p.stats.replaceChildren(
    stat('t', fmt(f.t_ms / 1000, 1) + ' s', 't'),
    stat('tip', f.tip_mm ? f.tip_mm.map((v) => v.toFixed(1)).join(', ') : '–', 'tip'),
    stat('hand', fmt(forces.hand_mN) + ' mN'),
    stat('wall peak', fmt(forces.wall_peak_mN) + ' mN', 'wall'),
    el('div', {}, 'fluoro ', fluoroOn ? el('span', { class: 'fluoro-on', 'data-stat': 'fluoro' }, 'ON') :
      el('b', { 'data-stat': 'fluoro' }, fluoroTime === null ? 'none' : 'off'), fluoroTime === null ? '' : ' ' + fmt(fluoroTime) + ' s'),
    ...SHOWN_METRICS.filter((k) => k in m).map((k) => stat(k.replace(/_/g, ' '), fmt(m[k], 1), k)),
    // A rig paced in real time: the haptic ticks it has dropped (it fell behind the hand).
    ...('haptic_dropped_ticks' in m ? [stat('rig dropped', m.haptic_dropped_ticks + (m.haptic_dropped_ticks === 1 ? ' tick' : ' ticks'), 'dropped')] : []),
    ...(f.seq === undefined ? [] : [stat('frame', String(f.seq), 'seq')]),
    stat('drawn', String(p.drawn), 'drawn'),
  );
}

let lastSecond = performance.now();
let rendersThisSecond = 0;
let framesThisSecond = 0;
function loop(now) {
  for (const p of panels.values()) {
    if (p.frame && p.frame !== p.shown) { apply(p); framesThisSecond++; }
    p.view.render();
  }
  rendersThisSecond++;
  if (now - lastSecond >= 1000) {
    document.getElementById('rate-fps').textContent = (rendersThisSecond * 1000 / (now - lastSecond)).toFixed(1);
    document.getElementById('rate-frames').textContent = (framesThisSecond * 1000 / (now - lastSecond)).toFixed(1);
    rendersThisSecond = 0;
    framesThisSecond = 0;
    lastSecond = now;
  }
  requestAnimationFrame(loop);
}

if (requireUser(['instructor', 'admin'])) {
  connect();
  requestAnimationFrame(loop);
}

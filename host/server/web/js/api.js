// Shared by every page: the token (sessionStorage), fetch with it, the error line, the header.
// Plain ES module, no build step.

const TOKEN_KEY = 'cathbox.token';
const USER_KEY = 'cathbox.user';

export function token() { return sessionStorage.getItem(TOKEN_KEY); }
export function me() {
  const text = sessionStorage.getItem(USER_KEY);
  return text ? JSON.parse(text) : null;
}
export function isSupervisor(user) { return user && (user.role === 'instructor' || user.role === 'admin'); }

export class ApiError extends Error {
  constructor(status, message) { super(message); this.status = status; }
}

// fetch('/api/v1' + path) with the bearer token; JSON in and out unless `raw` (an ArrayBuffer).
export async function api(path, { method = 'GET', body, raw = false, bytes } = {}) {
  const headers = {};
  if (token()) headers.Authorization = 'Bearer ' + token();
  let payload;
  if (bytes !== undefined) { headers['Content-Type'] = 'application/octet-stream'; payload = bytes; }
  else if (body !== undefined) { headers['Content-Type'] = 'application/json'; payload = JSON.stringify(body); }
  const res = await fetch('/api/v1' + path, { method, headers, body: payload });
  if (res.status === 401 && path !== '/login') {
    logoutLocal();
    location.href = '/?expired=1';
    throw new ApiError(401, 'session expired: log in again');
  }
  if (!res.ok) {
    let line = res.status + ' ' + res.statusText;
    try { const j = await res.json(); if (j.error) line = j.error; } catch (_) { /* not JSON */ }
    throw new ApiError(res.status, line);
  }
  if (res.status === 204) return null;
  return raw ? res.arrayBuffer() : res.json();
}

export async function login(name, password) {
  const r = await api('/login', { method: 'POST', body: { name, password } });
  sessionStorage.setItem(TOKEN_KEY, r.token);
  sessionStorage.setItem(USER_KEY, JSON.stringify(r.user));
  return r.user;
}

function logoutLocal() { sessionStorage.removeItem(TOKEN_KEY); sessionStorage.removeItem(USER_KEY); }

export async function logout() {
  try { await api('/logout', { method: 'POST' }); } catch (_) { /* already gone */ }
  logoutLocal();
  location.href = '/';
}

// The error line of the page (one line, as the server wrote it).
export function showError(message) {
  const el = document.getElementById('error');
  if (!el) return;
  el.textContent = message || '';
  el.hidden = !message;
}

// Runs `fn`, showing any error on the error line.
export async function guarded(fn) {
  try { showError(''); return await fn(); } catch (e) { showError(e.message); return undefined; }
}

const PAGES = [
  { href: '/', label: 'Home', roles: ['trainee', 'instructor', 'admin'] },
  { href: '/live.html', label: 'Live', roles: ['instructor', 'admin'] },
  { href: '/results.html', label: 'Results', roles: ['instructor', 'admin'] },
  { href: '/trainee.html', label: 'My training', roles: ['trainee'] },
  { href: '/train.html', label: 'Train', roles: ['trainee'] },
  { href: '/admin.html', label: 'Admin', roles: ['admin'] },
];

// The page header for the user, or null: a visitor without a token is sent to the login, one of
// another role sees why the page is not theirs (the server refuses its API calls anyway).
export function requireUser(roles) {
  const user = me();
  if (!user || !token()) { location.href = '/'; return null; }
  renderNav(user);
  if (roles && !roles.includes(user.role)) {
    document.querySelector('main').innerHTML =
      '<p class="refused" id="refused">This page is for ' + roles.join(' and ') + 's; you are logged in as ' +
      escapeHtml(user.name) + ' (' + user.role + ').</p>';
    return null;
  }
  return user;
}

export function renderNav(user) {
  const nav = document.getElementById('nav');
  if (!nav) return;
  nav.innerHTML = '';
  const brand = document.createElement('span');
  brand.className = 'brand';
  brand.textContent = 'Cathbox';
  nav.appendChild(brand);
  for (const p of PAGES) {
    if (!p.roles.includes(user.role)) continue;
    const a = document.createElement('a');
    a.href = p.href;
    a.textContent = p.label;
    if (location.pathname === p.href || (p.href === '/' && location.pathname === '/index.html')) a.className = 'here';
    nav.appendChild(a);
  }
  const who = document.createElement('span');
  who.className = 'who';
  who.textContent = user.name + ' (' + user.role + ')';
  nav.appendChild(who);
  const out = document.createElement('button');
  out.textContent = 'Log out';
  out.id = 'logout';
  out.onclick = logout;
  nav.appendChild(out);
}

export function escapeHtml(s) {
  return String(s).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c]);
}

export function fmt(v, digits = 1) {
  if (v === null || v === undefined) return '–';
  if (typeof v !== 'number') return String(v);
  return Number.isInteger(v) ? String(v) : v.toFixed(digits);
}

export function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c instanceof Node ? c : document.createTextNode(String(c)));
  return e;
}

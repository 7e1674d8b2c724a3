// Login, then a home page with what the user's role may do.
import { login, me, token, renderNav, showError, el } from './api.js';

const CARDS = {
  instructor: [
    ['/live.html', 'Live', 'The rigs in session now: watch one or several side by side.'],
    ['/results.html', 'Results', 'Every run: filter, sort, export as CSV; learning curves per trainee.'],
  ],
  trainee: [
    ['/trainee.html', 'My training', 'My assignments, my results and my learning curves.'],
    ['/train.html', 'Train', 'Run an assigned case here in the browser, with the keyboard.'],
  ],
  admin: [
    ['/admin.html', 'Admin', 'Users and roles; upload cases.'],
    ['/live.html', 'Live', 'The rigs in session now.'],
    ['/results.html', 'Results', 'Every run, learning curves, CSV.'],
  ],
};

function showHome(user) {
  renderNav(user);
  document.getElementById('login').hidden = true;
  document.getElementById('home').hidden = false;
  document.getElementById('welcome').textContent = 'Welcome, ' + user.name;
  const cards = document.getElementById('cards');
  cards.innerHTML = '';
  for (const [href, title, text] of CARDS[user.role] || []) {
    cards.append(el('a', { class: 'card', href, 'data-page': href }, el('h2', {}, title), el('p', { class: 'muted' }, text)));
  }
}

const user = me();
if (user && token()) {
  showHome(user);
} else {
  const form = document.getElementById('login');
  form.hidden = false;
  if (new URLSearchParams(location.search).has('expired')) showError('session expired: log in again');
  form.addEventListener('submit', async (e) => {
    e.preventDefault();
    try {
      showError('');
      showHome(await login(document.getElementById('name').value, document.getElementById('password').value));
    } catch (err) {
      showError(err.message);
    }
  });
}

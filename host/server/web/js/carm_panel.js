// The C-arm panel of the trainee page: cathbox-trainer's C-arm controls (host/app carm_panel.cpp)
// for the fluoroscopic view. LAO/RAO and cranial/caudal angles, the standard and the case's
// working projections, the table height, the detector's field of view (zoom) and the pulse rate.
// Each edit goes to the haptic worker (message `carm`), which posts it through the native panel's
// model (app::CArmPanelModel: the same ranges, the same session controls, so the run's record holds
// it and replays with every hash); a refused value comes back as one line. The fields show the
// C-arm as the worker's frames say it is (never while one is being dragged).
const ANGLES = [['lao', 'LAO+ / RAO−', -120, 120, 1, '°'], ['cranial', 'cranial+ / caudal−', -60, 60, 1, '°']];
const GEOMETRY = [['table', 'table height', -200, 200, 5, ' mm'], ['fov', 'field of view', 100, 420, 10, ' mm']];
// cbx_carm_state's order.
const S = { lao: 0, cranial: 1, sid: 2, table: 3, fov: 4, collimation: 5, rate: 6, beam: 7, magnification: 8 };

function side(name, v) {
  if (name === 'lao') return v === 0 ? 'AP' : (v > 0 ? 'LAO ' : 'RAO ') + Math.abs(v).toFixed(0) + '°';
  return v === 0 ? '0°' : (v > 0 ? 'CRA ' : 'CAU ') + Math.abs(v).toFixed(0) + '°';
}

export class CArmPanel {
  // root: the panel's element; send(what, values): to the worker.
  constructor(root, send) {
    this.root = root;
    this.send = send;
    this.state = null;
    this.inputs = {};
    root.replaceChildren();
    const title = document.createElement('b');
    title.textContent = 'C-arm';
    root.append(title, ' ');
    this.pose = document.createElement('span');
    this.pose.id = 'carm-pose';
    root.append(this.pose);
    for (const [name, label, min, max, step] of [...ANGLES, ...GEOMETRY]) this.slider(name, label, min, max, step);
    const row = document.createElement('div');
    this.projection = document.createElement('select');
    this.projection.id = 'carm-projection';
    this.projection.addEventListener('change', () => this.pick());
    this.rate = document.createElement('select');
    this.rate.id = 'carm-rate';
    for (const r of [7.5, 15, 30]) this.rate.append(new Option(r + ' pulses/s', String(r)));
    this.rate.addEventListener('change', () => { this.send('rate', [Number(this.rate.value)]); this.rate.blur(); });
    row.append('projection ', this.projection, ' ', this.rate);
    this.note = document.createElement('div');
    this.note.id = 'carm-note';
    this.note.className = 'error-line';
    root.append(row, this.note);
  }

  slider(name, label, min, max, step) {
    const row = document.createElement('label');
    row.className = 'carm-row';
    const input = Object.assign(document.createElement('input'), { type: 'range', min, max, step, id: 'carm-' + name });
    const value = document.createElement('span');
    value.className = 'carm-value';
    input.addEventListener('input', () => { value.textContent = this.shown(name, Number(input.value)); });
    input.addEventListener('change', () => { this.edit(name); input.blur(); });  // the keys drive the tool again
    row.append(label + ' ', input, ' ', value);
    this.root.append(row);
    this.inputs[name] = { input, value };
  }

  shown(name, v) { return name === 'lao' || name === 'cranial' ? side(name, v) : v.toFixed(0) + ' mm'; }

  // The projections offered (the worker's ready message: standard, then the case's views).
  setProjections(list) {
    this.projections = list;
    this.projection.replaceChildren(new Option('pick…', ''), ...list.map((p, i) =>
      new Option(`${p.name} (${side('lao', p.lao)}, ${side('cranial', p.cranial)})`, String(i))));
  }

  pick() {
    const p = this.projections[Number(this.projection.value)];
    this.projection.value = '';
    this.projection.blur();
    if (p) this.send('angles', [p.lao, p.cranial]);
  }

  edit(name) {
    const v = (k) => Number(this.inputs[k].input.value);
    const s = this.state;
    if (name === 'lao' || name === 'cranial') this.send('angles', [v('lao'), v('cranial')]);
    else if (s) this.send('geometry', [s[S.sid], v('table'), v('fov'), s[S.collimation]]);
  }

  // The C-arm now (a frame's cbx_carm_state).
  update(state) {
    this.state = state;
    for (const [name, { input, value }] of Object.entries(this.inputs)) {
      if (document.activeElement === input) continue;  // being dragged
      const v = state[S[name]];
      if (Number(input.value) !== v) input.value = String(v);
      value.textContent = this.shown(name, v);
    }
    if (document.activeElement !== this.rate) this.rate.value = String(state[S.rate]);
    const text = `${side('lao', state[S.lao])}, ${side('cranial', state[S.cranial])}, field ${state[S.fov].toFixed(0)} mm, ` +
      `×${state[S.magnification].toFixed(2)} at the isocentre, ${state[S.beam] ? 'X-RAY' : 'pedal up'}`;
    if (this.pose.textContent !== text) this.pose.textContent = text;
  }

  refused(line) { this.note.textContent = line; }
}

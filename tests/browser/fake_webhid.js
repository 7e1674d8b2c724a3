// An emulated box behind WebHID for the trainee page's test (train_box.py): headless Chromium has
// no USB and no HID device, so this stands in for navigator.hid, in the two places the page uses it:
//   - the page (installed before its scripts, Page.addScriptToEvaluateOnNewDocument): Chromium's
//     chooser, which here always offers the one box (requestDevice), and window.fakeBox, the test's
//     handle on the box;
//   - the haptic worker, which owns the box (installed by the test through the DevTools protocol,
//     Runtime.evaluate in the worker's target, with self.FAKE_WEBHID = {backend, url} first):
//     getDevices() gives the box the page was allowed; the box behind it is either
//       'codec':  protocol/'s own codec (the page's cathbox-protocol.js and js/box_codec.js):
//                 feature reports answered as a box answers GET_REPORT (the ID first, as Chromium
//                 gives them), state reports encoded from what the test sets, OUT reports decoded
//                 and handed to the test;
//       'bridge': cathbox-emu's box through cathbox-box-bridge at `url` (the same 64-byte report
//                 bytes; a feature report asked for by its one-byte ID), so the worker's WebHID path
//                 runs end to end against the emulated firmware.
// The two halves talk over a BroadcastChannel. From the test, in the page:
//   await fakeBox.configure({calibration: {...}, limits: {...}})   (codec; before connecting)
//   await fakeBox.emit({insertion_count, rotation_count, ...})      (codec) one IN report to the worker
//   fakeBox.installed ('codec' | 'bridge' once the worker's half is in), fakeBox.commands (the
//   worker's commands, decoded: codec), fakeBox.refused, fakeBox.features_read, fakeBox.sent (bridge)
(() => {
  const VENDOR = 0x1209;
  const PRODUCT = 0xcb01;
  const NAME = 'Cathbox (fake WebHID)';
  const channel = new BroadcastChannel('cathbox-fake-webhid');
  const define = (proto, hid) => Object.defineProperty(proto, 'hid', { get: () => hid, configurable: true });

  if (typeof WorkerGlobalScope === 'undefined') {  // the page's half
    const box = { installed: null, commands: [], refused: [], features_read: [], sent: 0, allowed: false, asked: new Map(), next: 0 };
    channel.onmessage = (e) => {
      const m = e.data;
      if (m.op === 'installed') box.installed = m.backend;
      else if (m.op === 'command') box.commands.push(m.command);
      else if (m.op === 'refused') box.refused.push(m.message);
      else if (m.op === 'feature') box.features_read.push(m.id);
      else if (m.op === 'sent') box.sent = m.sent;
      else if (m.op === 'done' && box.asked.has(m.id)) { box.asked.get(m.id)(m.error || true); box.asked.delete(m.id); }
    };
    const ask = (op, body) => new Promise((resolve) => { const id = ++box.next; box.asked.set(id, resolve); channel.postMessage({ op, id, ...body }); });
    box.configure = (config) => ask('config', { config });
    box.emit = (state) => ask('emit', { state });
    const device = { vendorId: VENDOR, productId: PRODUCT, productName: NAME };
    define(Navigator.prototype, {
      async getDevices() { return box.allowed ? [device] : []; },
      async requestDevice({ filters }) {
        box.allowed = (filters || []).some((f) => f.vendorId === VENDOR && f.productId === PRODUCT);
        return box.allowed ? [device] : [];
      },
      addEventListener() {},
      removeEventListener() {},
    });
    window.fakeBox = box;
    return;
  }

  // The worker's half: only in the haptic worker whose session is open and running (js/train_worker.js's
  // own `sessionOpen` and `over`; the test evaluates this in every haptic worker the browser lists,
  // and the previous pages' may linger, kept for going back).
  // eslint-disable-next-line no-undef
  if (typeof sessionOpen === 'undefined' || !sessionOpen || over) return;
  // Once per worker: the test evaluates this again until the page hears that it is in.
  if (self.fakeWebhidInstalled) return;
  self.fakeWebhidInstalled = true;
  const setup = self.FAKE_WEBHID || { backend: 'codec' };
  const say = (m) => channel.postMessage(m);
  const listeners = { inputreport: [], disconnect: [] };
  let codec = null;
  const loadCodec = () => {
    if (!codec) {
      if (!self.CathboxProtocol) importScripts('/wasm/cathbox-protocol.js');
      codec = Promise.all([import('/js/box_codec.js'), self.CathboxProtocol({ locateFile: (p) => '/wasm/' + p, mainScriptUrlOrBlob: '/wasm/cathbox-protocol.js' })])
        .then(([{ BoxCodec }, m]) => new BoxCodec(m));
    }
    return codec;
  };
  const inputReport = (device, bytes) => {
    const event = { type: 'inputreport', device, reportId: bytes[0], data: new DataView(bytes.buffer, bytes.byteOffset + 1, 63) };
    listeners.inputreport.forEach((f) => f(event));
  };
  const device = {
    vendorId: VENDOR, productId: PRODUCT, productName: NAME, opened: false, collections: [{ usagePage: 0xff00, usage: 1 }],
    addEventListener(type, f) { if (type === 'inputreport') listeners.inputreport.push(f); },
    removeEventListener() {},
    async sendFeatureReport() { throw new DOMException('not emulated', 'NotSupportedError'); },
  };

  if (setup.backend === 'bridge') {
    let ws = null;
    const asked = [];  // feature requests waiting, in order
    let sent = 0;
    device.open = () => new Promise((resolve, reject) => {
      ws = new WebSocket(setup.url);
      ws.binaryType = 'arraybuffer';
      ws.onopen = () => { device.opened = true; resolve(); };
      ws.onmessage = (e) => {
        const bytes = new Uint8Array(e.data);
        const i = asked.findIndex((a) => a.id === bytes[0]);
        if (i >= 0 && bytes[0] !== 0x01 && (bytes.length === 1 || bytes.length === 64)) return asked.splice(i, 1)[0].answer(bytes);
        inputReport(device, bytes);
      };
      ws.onclose = (e) => {
        if (!device.opened) return reject(new DOMException('fake WebHID: ' + setup.url + ': ' + e.code, 'NetworkError'));
        device.opened = false;
        listeners.disconnect.forEach((f) => f({ type: 'disconnect', device }));
      };
    });
    device.close = async () => { if (ws) ws.close(1000, 'closed'); };
    device.receiveFeatureReport = (id) => new Promise((resolve, reject) => {
      asked.push({ id, answer: (bytes) => (bytes.length === 1 ? reject(new DOMException('stalled', 'NotAllowedError')) : resolve(new DataView(bytes.buffer))) });
      say({ op: 'feature', id });
      ws.send(new Uint8Array([id]));
    });
    device.sendReport = async (id, data) => {
      const bytes = new Uint8Array(64);
      bytes[0] = id;
      bytes.set(new Uint8Array(data.buffer || data, data.byteOffset || 0, Math.min(63, data.byteLength)), 1);
      ws.send(bytes);
      if (++sent % 50 === 0) say({ op: 'sent', sent });
    };
  } else {
    const FEATURE = { device_info: 0x10, calibration: 0x11, limits: 0x12 };
    const config = {
      device_info: { version: 1, fw_major: 1, fw_minor: 0, fw_patch: 0, protocol_minor: 1, serial: 'FAKE-0001', board: 'fake-webhid',
        insertion_actuator: 1, rotation_actuator: 1, insertion_encoder_cpr: 2400, rotation_encoder_cpr: 4096, build: 'test' },
      calibration: { version: 1, insertion_counts_per_m: 108650, rotation_counts_per_rev: 4096, insertion_full_scale_mN: 5000,
        rotation_full_scale_uNm: 50000, insertion_curve_0_in: 250, insertion_curve_0_out: 250, insertion_curve_1_in: 500,
        insertion_curve_1_out: 500, insertion_curve_2_in: 750, insertion_curve_2_out: 750, insertion_curve_3_in: 1000,
        insertion_curve_3_out: 1000, rotation_curve_0_in: 250, rotation_curve_0_out: 250, rotation_curve_1_in: 500,
        rotation_curve_1_out: 500, rotation_curve_2_in: 750, rotation_curve_2_out: 750, rotation_curve_3_in: 1000, rotation_curve_3_out: 1000 },
      limits: { version: 1, max_force_mN: 5000, max_torque_uNm: 50000, watchdog_timeout_ms: 50, insertion_max_current_mA: 1500,
        rotation_max_current_mA: 1000, force_slew_mN_per_ms: 100, torque_slew_uNm_per_ms: 1000 },
    };
    let seq = 0;
    let features = 0;
    device.open = async () => { await loadCodec(); device.opened = true; };
    device.close = async () => { device.opened = false; };
    device.receiveFeatureReport = async (id) => {
      const c = await loadCodec();
      const name = Object.keys(FEATURE).find((k) => FEATURE[k] === id);
      if (!name) throw new DOMException('stalled', 'NotAllowedError');
      say({ op: 'feature', id });
      return new DataView(c.encodeFeature(id, { seq: ++features, ...config[name] }).buffer);
    };
    device.sendReport = async (id, data) => {
      const c = await loadCodec();
      const bytes = new Uint8Array(64);
      bytes[0] = id;
      bytes.set(new Uint8Array(data.buffer || data, data.byteOffset || 0, Math.min(63, data.byteLength)), 1);
      try { say({ op: 'command', command: c.decodeCommand(bytes) }); } catch (e) { say({ op: 'refused', message: e.message }); }
    };
    channel.onmessage = async (e) => {
      const m = e.data;
      try {
        if (m.op === 'config') for (const k of Object.keys(m.config)) Object.assign(config[k], m.config[k]);
        else if (m.op === 'emit') {  // one IN report, WebHID's event (the ID split off), handled before the answer
          const c = await loadCodec();
          seq = (seq + 1) & 0xffff;
          inputReport(device, c.encodeState({ seq, status: 0x2, ...m.state }));
        }
        say({ op: 'done', id: m.id });
      } catch (err) {
        say({ op: 'done', id: m.id, error: String(err) });
      }
    };
  }

  define(WorkerNavigator.prototype, {
    async getDevices() { return [device]; },
    addEventListener(type, f) { if (type === 'disconnect') listeners.disconnect.push(f); },
    removeEventListener() {},
  });
  say({ op: 'installed', backend: setup.backend });
})();

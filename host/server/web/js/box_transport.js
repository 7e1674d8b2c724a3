// How the trainee page reaches a box: 64-byte reports in and out, the same bytes whichever way.
// Both transports are driven from the haptic worker (js/train_worker.js), never the page's thread.
//   WebHID      navigator.hid (Chromium): the page asks for the box 1209:cb01 in Chromium's chooser
//               (askForBox: requestDevice needs a click on the page); the worker then finds the
//               permitted box with navigator.hid.getDevices() and owns it (open, inputreport,
//               sendReport, receiveFeatureReport). WebHID splits the report ID off, so it is put
//               back on the way in and taken off on the way out.
//   WebSocket   ?box=ws://HOST:PORT: cathbox-box-bridge in front of cathbox-emu, one binary
//               message a report; a feature report asked for by its one-byte ID, answered with
//               its 64 bytes or, refused, the ID alone (host/server/README.md).
// A transport calls onReport(Uint8Array(64)) for each IN report and onClose(reason) once; send(bytes)
// queues one OUT report (false when it could not); feature(id) resolves to a feature report's 64
// bytes with the ID at byte 0.
export const BOX_VENDOR = 0x1209;
export const BOX_PRODUCT = 0xcb01;
const USAGE_PAGE = 0xff00;

const FEATURE_WAIT_MS = 2000;

export class WebSocketBox {
  constructor(url) {
    this.url = url;
    this.onReport = () => {};
    this.onClose = () => {};
    this.asked = [];  // feature requests waiting for the bridge's answer, in order
  }

  // GET_REPORT through the bridge: the ID out, the report (or the ID alone: refused) back.
  feature(id) {
    return new Promise((resolve, reject) => {
      if (!this.ws || this.ws.readyState !== WebSocket.OPEN) return reject(new Error(this.url + ': not open'));
      const hex = '0x' + id.toString(16).padStart(2, '0');
      const timer = setTimeout(() => {
        this.asked = this.asked.filter((a) => a.timer !== timer);
        reject(new Error('feature report ' + hex + ': no answer from the bridge in ' + FEATURE_WAIT_MS + ' ms'));
      }, FEATURE_WAIT_MS);
      this.asked.push({ id, timer, resolve, reject: () => reject(new Error('feature report ' + hex + ': the box refused it')) });
      this.ws.send(new Uint8Array([id]));
    });
  }

  // A feature answer for the oldest request of its ID, or false (an IN report).
  answered(bytes) {
    const i = this.asked.findIndex((a) => a.id === bytes[0]);
    if (i < 0 || (bytes.length !== 1 && bytes.length !== 64) || bytes[0] === 0x01) return false;
    const [a] = this.asked.splice(i, 1);
    clearTimeout(a.timer);
    if (bytes.length === 1) a.reject(); else a.resolve(bytes);
    return true;
  }

  describe() { return 'the box bridge at ' + this.url; }

  open() {
    return new Promise((resolve, reject) => {
      const ws = new WebSocket(this.url);
      ws.binaryType = 'arraybuffer';
      let opened = false;
      ws.onopen = () => { opened = true; this.ws = ws; resolve(this); };
      ws.onmessage = (e) => {
        if (!(e.data instanceof ArrayBuffer)) return this.close('the bridge sent text, not a report');
        const bytes = new Uint8Array(e.data);
        if (!this.answered(bytes)) this.onReport(bytes);
      };
      ws.onclose = (e) => {
        const reason = this.url + ': ' + (e.reason || 'closed (code ' + e.code + ')');
        if (!opened) reject(new Error(reason)); else this.onClose(reason);
      };
    });
  }

  send(bytes) {
    if (!this.ws || this.ws.readyState !== WebSocket.OPEN) return false;
    this.ws.send(bytes);
    return true;
  }

  close(reason) {
    if (this.ws) this.ws.close(1000, reason ? String(reason).slice(0, 120) : undefined);
  }
}

const isBox = (d) => d.vendorId === BOX_VENDOR && d.productId === BOX_PRODUCT;

// On the page, from a click: Chromium's chooser for the box (a box allowed before is there without
// asking). Resolves to the device's name, or null when none was chosen.
export async function askForBox() {
  const allowed = (await navigator.hid.getDevices()).filter(isBox);
  const [device] = allowed.length ? allowed : await navigator.hid.requestDevice({ filters: [{ vendorId: BOX_VENDOR, productId: BOX_PRODUCT, usagePage: USAGE_PAGE }] });
  return device ? device.productName || 'Cathbox' : null;
}

// In the haptic worker: the box the page was allowed (askForBox), from navigator.hid.getDevices().
export class WebHidBox {
  constructor() {
    this.onReport = () => {};
    this.onClose = () => {};
  }

  describe() { return this.device ? 'WebHID ' + this.device.productName : 'WebHID'; }

  async open() {
    if (!('hid' in navigator)) throw new Error('WebHID: not available in the haptic worker');
    const [device] = (await navigator.hid.getDevices()).filter(isBox);
    if (!device) throw new Error('WebHID: no box allowed for this page (Connect box asks for one)');
    if (!device.opened) await device.open();
    this.device = device;
    device.addEventListener('inputreport', (e) => {
      const bytes = new Uint8Array(64);
      bytes[0] = e.reportId;
      bytes.set(new Uint8Array(e.data.buffer, e.data.byteOffset, Math.min(63, e.data.byteLength)), 1);
      this.onReport(bytes);
    });
    navigator.hid.addEventListener('disconnect', (e) => { if (e.device === device) this.onClose('the box was unplugged'); });
    return this;
  }

  // A feature report (GET_REPORT on the control endpoint) as 64 bytes, its ID at byte 0. Chromium
  // gives the report with its ID first; a 63-byte payload without it gets it put back.
  async feature(id) {
    const view = await this.device.receiveFeatureReport(id);
    const data = new Uint8Array(view.buffer, view.byteOffset, view.byteLength);
    if (data.length === 64 && data[0] === id) return data.slice();
    const bytes = new Uint8Array(64);
    bytes[0] = id;
    bytes.set(data.subarray(0, 63), 1);
    return bytes;
  }

  send(bytes) {
    if (!this.device) return false;
    this.device.sendReport(bytes[0], bytes.subarray(1)).catch((err) => this.onClose('WebHID: ' + err.message));
    return true;
  }

  close() { if (this.device) this.device.close(); }
}

// The box the page's address asks for: ?box=ws://... (the bridge), else WebHID where the browser
// has it (after a click), else why not (the keyboard stays). {kind: 'bridge', url} | {kind: 'webhid'}
// | {kind: null, why}.
export function chooseBox(params) {
  const url = params.get('box');
  if (url) {
    if (!/^wss?:\/\//.test(url)) return { kind: null, why: '?box=' + url + ': a ws:// or wss:// address expected' };
    return { kind: 'bridge', url };
  }
  if ('hid' in navigator) return { kind: 'webhid' };
  return { kind: null, why: 'This browser has no WebHID (and no ?box=ws://… bridge was given): the keyboard drives the tool.' };
}

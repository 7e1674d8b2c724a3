// An emulated box behind WebHID for the trainee page's test (train_test.py): headless Chromium
// has no USB and no HID device, so this stands in for navigator.hid. It speaks the box protocol
// with protocol/'s own codec (cathbox-protocol.js and js/box_codec.js, the page's own files):
// feature reports answered as a box answers GET_REPORT (the ID first, as Chromium gives them),
// state reports encoded from what the test sets, OUT reports decoded and kept. Installed before
// the page's scripts (Page.addScriptToEvaluateOnNewDocument); the test drives it through
// window.fakeBox:
//   fakeBox.config = {calibration: {...}, limits: {...}, device_info: {...}}   (before connecting)
//   await fakeBox.emit({insertion_count, rotation_count, ...})   one IN report to the page
//   fakeBox.commands                                              the page's commands, decoded
(() => {
  const VENDOR = 0x1209;
  const PRODUCT = 0xcb01;
  let codec = null;
  const loadCodec = () => {
    if (!codec) {
      codec = new Promise((resolve, reject) => {
        const s = document.createElement('script');
        s.src = '/wasm/cathbox-protocol.js';
        s.onload = async () => {
          const { BoxCodec } = await import('/js/box_codec.js');
          resolve(new BoxCodec(await self.CathboxProtocol({ locateFile: (p) => '/wasm/' + p })));
        };
        s.onerror = () => reject(new Error('fake WebHID: /wasm/cathbox-protocol.js not served'));
        document.head.append(s);
      });
    }
    return codec;
  };
  const FEATURE = { device_info: 0x10, calibration: 0x11, limits: 0x12 };
  const box = {
    config: {
      device_info: { version: 1, fw_major: 1, fw_minor: 0, fw_patch: 0, protocol_minor: 1, serial: 'FAKE-0001', board: 'fake-webhid',
        insertion_actuator: 1, rotation_actuator: 1, insertion_encoder_cpr: 2400, rotation_encoder_cpr: 4096, build: 'test' },
      calibration: { version: 1, insertion_counts_per_m: 108650, rotation_counts_per_rev: 4096, insertion_full_scale_mN: 5000,
        rotation_full_scale_uNm: 50000, insertion_curve_3_in: 1000, insertion_curve_3_out: 1000, rotation_curve_3_in: 1000,
        rotation_curve_3_out: 1000, insertion_curve_0_in: 250, insertion_curve_0_out: 250, insertion_curve_1_in: 500,
        insertion_curve_1_out: 500, insertion_curve_2_in: 750, insertion_curve_2_out: 750, rotation_curve_0_in: 250,
        rotation_curve_0_out: 250, rotation_curve_1_in: 500, rotation_curve_1_out: 500, rotation_curve_2_in: 750, rotation_curve_2_out: 750 },
      limits: { version: 1, max_force_mN: 5000, max_torque_uNm: 50000, watchdog_timeout_ms: 50, insertion_max_current_mA: 1500,
        rotation_max_current_mA: 1000, force_slew_mN_per_ms: 100, torque_slew_uNm_per_ms: 1000 },
    },
    commands: [],
    refused: [],
    features_read: [],
    seq: 0,
  };
  const listeners = [];
  const device = {
    vendorId: VENDOR, productId: PRODUCT, productName: 'Cathbox (fake WebHID)', opened: false,
    collections: [{ usagePage: 0xff00, usage: 1 }],
    async open() { await loadCodec(); this.opened = true; },
    async close() { this.opened = false; },
    addEventListener(type, f) { if (type === 'inputreport') listeners.push(f); },
    removeEventListener() {},
    async receiveFeatureReport(id) {
      const c = await loadCodec();
      const name = Object.keys(FEATURE).find((k) => FEATURE[k] === id);
      if (!name) throw new DOMException('stalled', 'NotAllowedError');
      box.features_read.push(id);
      const bytes = c.encodeFeature(id, { seq: box.features_read.length, ...box.config[name] });
      return new DataView(bytes.buffer);
    },
    async sendReport(id, data) {
      const c = await loadCodec();
      const bytes = new Uint8Array(64);
      bytes[0] = id;
      bytes.set(new Uint8Array(data.buffer || data, data.byteOffset || 0, Math.min(63, data.byteLength)), 1);
      try { box.commands.push(c.decodeCommand(bytes)); } catch (e) { box.refused.push(e.message); }
    },
    async sendFeatureReport() { throw new DOMException('not emulated', 'NotSupportedError'); },
  };
  box.device = device;
  // One IN report: the state's fields through the codec, WebHID's event (the ID split off).
  box.emit = async (state) => {
    const c = await loadCodec();
    box.seq = (box.seq + 1) & 0xffff;
    const bytes = c.encodeState({ seq: box.seq, status: 0x2, ...state });
    const event = { type: 'inputreport', device, reportId: bytes[0], data: new DataView(bytes.buffer, 1, 63) };
    listeners.forEach((f) => f(event));
  };
  const hid = {
    async getDevices() { return []; },
    async requestDevice({ filters }) {
      const fits = (filters || []).some((f) => f.vendorId === VENDOR && f.productId === PRODUCT);
      return fits ? [device] : [];
    },
    addEventListener() {},
    removeEventListener() {},
  };
  Object.defineProperty(Navigator.prototype, 'hid', { get: () => hid, configurable: true });
  window.fakeBox = box;
})();

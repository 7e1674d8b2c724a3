// The box protocol for a page or worker, spoken by protocol/'s own C codec compiled to
// WebAssembly (cathbox-protocol.js, host/wasm/src/protocol_exports.c): no second implementation
// in JavaScript. `module` is the instantiated CathboxProtocol module (browser or node).
//   const codec = new BoxCodec(await CathboxProtocol());
//   codec.decodeState(bytes64)  -> {seq, time_us, insertion_count, ...} or throws 'IN report: crc'
//   codec.encodeCommand({seq, time_us, mode, flags, insertion: LAW, rotation: LAW}) -> Uint8Array(64)
//     LAW = {offset, pos0, stiffness, damping, out_min, out_max} (protocol/README.md units)
//   codec.decodeFeature(FEATURE.calibration, bytes64) -> {insertion_counts_per_m, ...} or throws
//     'feature report 0x11: crc'; device info, calibration and limits (what a page reads on connect)
//   codec.encodeFeature(FEATURE.limits, {...}) -> Uint8Array(64) (what a box answers: tests)
//   codec.encodeState({...}), codec.decodeCommand(bytes64): the box's side (tests' emulated device)
export const REPORT_SIZE = 64;
export const STATE_FIELDS = ['version', 'seq', 'time_us', 'insertion_count', 'rotation_count', 'insertion_vel_cps',
  'rotation_vel_cps', 'insertion_force_mN', 'rotation_torque_uNm', 'insertion_current_mA', 'rotation_current_mA', 'status',
  'faults', 'command_seq_echo', 'encoder_errors', 'rx_errors', 'mode', 'board_faults', 'in_dropped'];
export const LAW_FIELDS = ['offset', 'pos0', 'stiffness', 'damping', 'out_min', 'out_max'];
const COMMAND_HEAD = ['seq', 'time_us', 'mode', 'flags'];
export const FEATURE = { device_info: 0x10, calibration: 0x11, limits: 0x12 };
const HEADER = ['version', 'seq', 'time_us'];
const curve = (axis) => [0, 1, 2, 3].flatMap((i) => [axis + '_curve_' + i + '_in', axis + '_curve_' + i + '_out']);
// Field order of host/wasm/src/feature_exports.c; the u32 ones are read back unsigned.
export const FEATURE_FIELDS = {
  [FEATURE.device_info]: [...HEADER, 'fw_major', 'fw_minor', 'fw_patch', 'protocol_minor', 'insertion_actuator',
    'rotation_actuator', 'insertion_encoder_cpr', 'rotation_encoder_cpr'],
  [FEATURE.calibration]: [...HEADER, 'insertion_counts_per_m', 'rotation_counts_per_rev', 'insertion_full_scale_mN',
    'rotation_full_scale_uNm', ...curve('insertion'), ...curve('rotation')],
  [FEATURE.limits]: [...HEADER, 'max_force_mN', 'max_torque_uNm', 'watchdog_timeout_ms', 'insertion_max_current_mA',
    'rotation_max_current_mA', 'force_slew_mN_per_ms', 'torque_slew_uNm_per_ms'],
};
const UNSIGNED = new Set(['time_us', 'insertion_encoder_cpr', 'rotation_encoder_cpr', 'insertion_counts_per_m',
  'rotation_counts_per_rev', 'insertion_full_scale_mN', 'rotation_full_scale_uNm', 'max_force_mN', 'max_torque_uNm']);
const TEXT = ['serial', 'board', 'build'];
const TEXT_STRIDE = 17;
const hex = (id) => '0x' + id.toString(16).padStart(2, '0');

export class BoxCodec {
  constructor(module) {
    this.m = module;
    this.stateDecode = module.cwrap('cbxw_state_decode', 'number', ['number', 'number', 'number']);
    this.commandEncode = module.cwrap('cbxw_command_encode', 'number', ['number', 'number']);
    this.statusName = module.cwrap('cbxw_status_name', 'string', ['number']);
    this.stateEncode = module.cwrap('cbxw_state_encode', 'number', ['number', 'number']);
    this.commandDecode = module.cwrap('cbxw_command_decode', 'number', ['number', 'number', 'number']);
    this.featureDecode = module.cwrap('cbxw_feature_decode', 'number', ['number', 'number', 'number', 'number', 'number']);
    this.featureEncode = module.cwrap('cbxw_feature_encode', 'number', ['number', 'number', 'number', 'number']);
    this.bytes = module._malloc(REPORT_SIZE);
    this.fields = module._malloc(4 * 32);
    this.text = module._malloc(3 * TEXT_STRIDE);
  }

  // Bytes (Uint8Array, DataView or ArrayBuffer) copied into the module; their length.
  put(report, what) {
    const bytes = report instanceof Uint8Array ? report
      : new Uint8Array(report.buffer || report, report.byteOffset || 0, report.byteLength);
    if (bytes.length > REPORT_SIZE) throw new Error(what + ': ' + bytes.length + ' bytes, ' + REPORT_SIZE + ' expected');
    this.m.HEAPU8.set(bytes, this.bytes);
    return bytes.length;
  }

  // A feature report (device info, calibration, limits; its ID at byte 0) to its fields.
  decodeFeature(id, report) {
    const what = 'feature report ' + hex(id);
    const names = FEATURE_FIELDS[id];
    if (!names) throw new Error(what + ': not one the page reads');
    const length = this.put(report, what);
    const status = this.featureDecode(id, this.bytes, length, this.fields, this.text);
    if (status !== 0) throw new Error(what + ': ' + this.statusName(status));
    const f = this.m.HEAP32.subarray(this.fields >> 2, (this.fields >> 2) + names.length);
    const out = {};
    names.forEach((name, i) => { out[name] = UNSIGNED.has(name) ? f[i] >>> 0 : f[i]; });
    if (id === FEATURE.device_info) TEXT.forEach((name, i) => { out[name] = this.m.UTF8ToString(this.text + i * TEXT_STRIDE); });
    return out;
  }

  // Fields to a feature report's 64 bytes (what a box answers); throws naming the encoder's status.
  encodeFeature(id, value) {
    const what = 'feature report ' + hex(id);
    const names = FEATURE_FIELDS[id];
    if (!names) throw new Error(what + ': not one the page reads');
    const f = this.m.HEAP32.subarray(this.fields >> 2, (this.fields >> 2) + names.length);
    names.forEach((name, i) => { f[i] = value[name] || 0; });
    this.m.HEAPU8.fill(0, this.text, this.text + 3 * TEXT_STRIDE);
    if (id === FEATURE.device_info) {
      TEXT.forEach((name, i) => {
        const s = String(value[name] || '');
        for (let k = 0; k < Math.min(s.length, TEXT_STRIDE - 1); ++k) this.m.HEAPU8[this.text + i * TEXT_STRIDE + k] = s.charCodeAt(k) & 0xff;
      });
    }
    const status = this.featureEncode(id, this.fields, this.text, this.bytes);
    if (status !== 0) throw new Error(what + ': ' + this.statusName(status));
    return this.m.HEAPU8.slice(this.bytes, this.bytes + REPORT_SIZE);
  }

  // An IN report's bytes (Uint8Array, DataView or ArrayBuffer) to its fields.
  decodeState(report) {
    const length = this.put(report, 'IN report');
    const status = this.stateDecode(this.bytes, length, this.fields);
    if (status !== 0) throw new Error('IN report: ' + this.statusName(status));
    const f = this.m.HEAP32.subarray(this.fields >> 2, (this.fields >> 2) + STATE_FIELDS.length);
    const state = {};
    STATE_FIELDS.forEach((name, i) => { state[name] = name === 'time_us' ? f[i] >>> 0 : f[i]; });
    return state;
  }

  // A state to its 64 bytes (fields missing are 0; version 1 unless given).
  encodeState(state) {
    const f = this.m.HEAP32.subarray(this.fields >> 2, (this.fields >> 2) + STATE_FIELDS.length);
    STATE_FIELDS.forEach((name, i) => { f[i] = state[name] || 0; });
    if (state.version === undefined) f[0] = 1;
    const status = this.stateEncode(this.fields, this.bytes);
    if (status !== 0) throw new Error('IN report: ' + this.statusName(status));
    return this.m.HEAPU8.slice(this.bytes, this.bytes + REPORT_SIZE);
  }

  // An OUT report's bytes to {seq, time_us, mode, flags, insertion: LAW, rotation: LAW}.
  decodeCommand(report) {
    const length = this.put(report, 'OUT report');
    const status = this.commandDecode(this.bytes, length, this.fields);
    if (status !== 0) throw new Error('OUT report: ' + this.statusName(status));
    const f = this.m.HEAP32.subarray(this.fields >> 2, (this.fields >> 2) + 16);
    const law = (o) => Object.fromEntries(LAW_FIELDS.map((name, i) => [name, f[o + i]]));
    return { seq: f[0], time_us: f[1] >>> 0, mode: f[2], flags: f[3], insertion: law(4), rotation: law(10) };
  }

  // A command to its 64 bytes; throws naming the encoder's status (a law out of range).
  encodeCommand(command) {
    const f = this.m.HEAP32.subarray(this.fields >> 2, (this.fields >> 2) + 16);
    COMMAND_HEAD.forEach((name, i) => { f[i] = command[name] || 0; });
    LAW_FIELDS.forEach((name, i) => { f[4 + i] = command.insertion[name]; f[10 + i] = command.rotation[name]; });
    const status = this.commandEncode(this.fields, this.bytes);
    if (status !== 0) throw new Error('OUT command: ' + this.statusName(status));
    return this.m.HEAPU8.slice(this.bytes, this.bytes + REPORT_SIZE);
  }
}

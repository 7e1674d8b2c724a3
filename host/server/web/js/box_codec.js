// The box protocol for a page or worker, spoken by protocol/'s own C codec compiled to
// WebAssembly (cathbox-protocol.js, host/wasm/src/protocol_exports.c): no second implementation
// in JavaScript. `module` is the instantiated CathboxProtocol module (browser or node).
//   const codec = new BoxCodec(await CathboxProtocol());
//   codec.decodeState(bytes64)  -> {seq, time_us, insertion_count, ...} or throws 'IN report: crc'
//   codec.encodeCommand({seq, time_us, mode, flags, insertion: LAW, rotation: LAW}) -> Uint8Array(64)
//     LAW = {offset, pos0, stiffness, damping, out_min, out_max} (protocol/README.md units)
export const REPORT_SIZE = 64;
export const STATE_FIELDS = ['version', 'seq', 'time_us', 'insertion_count', 'rotation_count', 'insertion_vel_cps',
  'rotation_vel_cps', 'insertion_force_mN', 'rotation_torque_uNm', 'insertion_current_mA', 'rotation_current_mA', 'status',
  'faults', 'command_seq_echo', 'encoder_errors', 'rx_errors', 'mode', 'board_faults', 'in_dropped'];
export const LAW_FIELDS = ['offset', 'pos0', 'stiffness', 'damping', 'out_min', 'out_max'];
const COMMAND_HEAD = ['seq', 'time_us', 'mode', 'flags'];

export class BoxCodec {
  constructor(module) {
    this.m = module;
    this.stateDecode = module.cwrap('cbxw_state_decode', 'number', ['number', 'number', 'number']);
    this.commandEncode = module.cwrap('cbxw_command_encode', 'number', ['number', 'number']);
    this.statusName = module.cwrap('cbxw_status_name', 'string', ['number']);
    this.bytes = module._malloc(REPORT_SIZE);
    this.fields = module._malloc(4 * 32);
  }

  // An IN report's bytes (Uint8Array, DataView or ArrayBuffer) to its fields.
  decodeState(report) {
    const bytes = report instanceof Uint8Array ? report
      : new Uint8Array(report.buffer || report, report.byteOffset || 0, report.byteLength);
    if (bytes.length > REPORT_SIZE) throw new Error('IN report: ' + bytes.length + ' bytes, ' + REPORT_SIZE + ' expected');
    this.m.HEAPU8.set(bytes, this.bytes);
    const status = this.stateDecode(this.bytes, bytes.length, this.fields);
    if (status !== 0) throw new Error('IN report: ' + this.statusName(status));
    const f = this.m.HEAP32.subarray(this.fields >> 2, (this.fields >> 2) + STATE_FIELDS.length);
    const state = {};
    STATE_FIELDS.forEach((name, i) => { state[name] = name === 'time_us' ? f[i] >>> 0 : f[i]; });
    return state;
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

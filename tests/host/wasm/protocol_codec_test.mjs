// protocol/'s codec compiled to WebAssembly (cathbox-protocol.js) and its JavaScript face
// (host/server/web/js/box_codec.js) against the golden vectors (protocol/vectors), under node:
//  - every vector through the wasm build's own cbx_vector_decode/encode (good ones round trip
//    byte for byte, bad ones are refused with their status);
//  - every good state vector's bytes decoded by BoxCodec.decodeState to the vector's value,
//    field by field; every bad state vector refused with its status's name;
//  - every good state vector's value encoded back by encodeState to its bytes (the tests'
//    emulated WebHID device speaks with it);
//  - every good command vector's value encoded by BoxCodec.encodeCommand to its bytes, and its
//    bytes decoded by decodeCommand to its value;
//  - every device info, calibration and limits vector (the feature reports a page reads on
//    connect) decoded by BoxCodec.decodeFeature to its value field by field (text too) and
//    encoded back by encodeFeature to its bytes; the bad ones refused with their status's name.
//   node protocol_codec_test.mjs build/wasm/bin/cathbox-protocol.js host/server/web/js/box_codec.js
import { createRequire } from 'module';
import { pathToFileURL } from 'url';
import path from 'path';

const [modulePath, codecPath] = process.argv.slice(2);
const require = createRequire(import.meta.url);
const CathboxProtocol = require(path.resolve(modulePath));
const { BoxCodec, STATE_FIELDS, FEATURE, FEATURE_FIELDS } = await import(pathToFileURL(path.resolve(codecPath)).href);

const m = await CathboxProtocol();
const codec = new BoxCodec(m);
const c = (name, ret, args) => m.cwrap(name, ret, args);
const count = c('cbxw_vector_count', 'number', [])();
const name = c('cbxw_vector_name', 'string', ['number']);
const kind = c('cbxw_vector_kind', 'string', ['number']);
const expect = c('cbxw_vector_expect', 'number', ['number']);
const length = c('cbxw_vector_length', 'number', ['number']);
const bytesAt = c('cbxw_vector_bytes', 'number', ['number']);
const fieldsOf = c('cbxw_vector_fields', 'number', ['number', 'number']);
const check = c('cbxw_vector_check', 'number', ['number']);
const statusName = c('cbxw_status_name', 'string', ['number']);
const scratch = m._malloc(4 * 32);

const failures = [];
let states = 0;
let commands = 0;
let features = 0;
const featureFieldsOf = c('cbxw_vector_feature_fields', 'number', ['number', 'number', 'number']);
const text = m._malloc(3 * 17);
for (let i = 0; i < count; ++i) {
  const what = name(i) + ' (' + kind(i) + ')';
  const r = check(i);
  if (r !== 0) failures.push(what + ': the wasm codec disagrees with the vector (' + r + ')');
  const bytes = m.HEAPU8.slice(bytesAt(i), bytesAt(i) + length(i));
  const n = fieldsOf(i, scratch);
  const golden = Array.from(m.HEAP32.subarray(scratch >> 2, (scratch >> 2) + n));
  if (kind(i) === 'state') {
    ++states;
    if (expect(i) === 0) {
      const s = codec.decodeState(bytes);
      STATE_FIELDS.forEach((f, k) => {
        const want = f === 'time_us' ? golden[k] >>> 0 : golden[k];
        if (s[f] !== want) failures.push(what + ': ' + f + ' ' + s[f] + ', ' + want + ' expected');
      });
      if (Buffer.compare(Buffer.from(codec.encodeState(s)), Buffer.from(bytes)) !== 0) failures.push(what + ': encodeState gives other bytes');
    } else {
      let line = null;
      try { codec.decodeState(bytes); } catch (e) { line = e.message; }
      if (line !== 'IN report: ' + statusName(expect(i))) failures.push(what + ': refused as ' + line);
    }
  } else if (kind(i) === 'command' && expect(i) === 0) {
    ++commands;
    const law = (o) => ({ offset: golden[o], pos0: golden[o + 1], stiffness: golden[o + 2], damping: golden[o + 3], out_min: golden[o + 4], out_max: golden[o + 5] });
    const out = codec.encodeCommand({ seq: golden[0], time_us: golden[1], mode: golden[2], flags: golden[3], insertion: law(4), rotation: law(10) });
    if (Buffer.compare(Buffer.from(out), Buffer.from(bytes)) !== 0) failures.push(what + ': encodeCommand gives other bytes');
    const back = codec.decodeCommand(bytes);
    if (JSON.stringify(back) !== JSON.stringify({ seq: golden[0], time_us: golden[1] >>> 0, mode: golden[2], flags: golden[3], insertion: law(4), rotation: law(10) })) {
      failures.push(what + ': decodeCommand gives ' + JSON.stringify(back));
    }
  } else if (FEATURE[kind(i)] !== undefined) {
    ++features;
    const id = FEATURE[kind(i)];
    if (expect(i) === 0) {
      const k = featureFieldsOf(i, scratch, text);
      const want = Array.from(m.HEAP32.subarray(scratch >> 2, (scratch >> 2) + k));
      const got = codec.decodeFeature(id, bytes);
      FEATURE_FIELDS[id].forEach((f, j) => {
        if ((got[f] | 0) !== want[j]) failures.push(what + ': ' + f + ' ' + got[f] + ', ' + want[j] + ' expected');
      });
      if (id === FEATURE.device_info) {
        ['serial', 'board', 'build'].forEach((f, j) => {
          const w = m.UTF8ToString(text + 17 * j);
          if (got[f] !== w) failures.push(what + ': ' + f + ' ' + JSON.stringify(got[f]) + ', ' + JSON.stringify(w) + ' expected');
        });
      }
      const again = codec.encodeFeature(id, got);
      if (Buffer.compare(Buffer.from(again), Buffer.from(bytes)) !== 0) failures.push(what + ': encodeFeature gives other bytes');
    } else {
      let line = null;
      try { codec.decodeFeature(id, bytes); } catch (e) { line = e.message; }
      const hexId = '0x' + id.toString(16);
      if (line !== 'feature report ' + hexId + ': ' + statusName(expect(i))) failures.push(what + ': refused as ' + line);
    }
  }
}
// The names, not only the order: three vectors' values by name, as protocol/vectors/VECTORS.md
// gives them.
const named = {
  device_info: { fw_major: 1, fw_minor: 2, fw_patch: 3, protocol_minor: 1, serial: 'CBX-0001', board: 'stm32f411-bp', build: '4cff6b7',
    insertion_actuator: 1, rotation_actuator: 1, insertion_encoder_cpr: 2400, rotation_encoder_cpr: 4096 },
  calibration_brake: { insertion_counts_per_m: 40000, rotation_counts_per_rev: 8192, insertion_full_scale_mN: 12000,
    rotation_full_scale_uNm: 15000, insertion_curve_0_in: 100, insertion_curve_0_out: 180, rotation_curve_3_in: 1000 },
  limits_default: { max_force_mN: 5000, max_torque_uNm: 50000, watchdog_timeout_ms: 50, insertion_max_current_mA: 1500,
    rotation_max_current_mA: 1000, force_slew_mN_per_ms: 100, torque_slew_uNm_per_ms: 1000 },
};
for (let i = 0; i < count; ++i) {
  const want = named[name(i)];
  if (!want) continue;
  const got = codec.decodeFeature(FEATURE[kind(i)], m.HEAPU8.slice(bytesAt(i), bytesAt(i) + length(i)));
  for (const [f, v] of Object.entries(want)) if (got[f] !== v) failures.push(name(i) + ': ' + f + ' ' + got[f] + ', ' + v + ' expected (VECTORS.md)');
  delete named[name(i)];
}
if (Object.keys(named).length) failures.push('vectors not found: ' + Object.keys(named));
let refused = null;
try {
  codec.encodeCommand({ seq: 1, mode: 1, insertion: { offset: 0, pos0: 0, stiffness: -1, damping: 0, out_min: 0, out_max: 0 },
    rotation: { offset: 0, pos0: 0, stiffness: 0, damping: 0, out_min: 0, out_max: 0 } });
} catch (e) { refused = e.message; }
if (refused !== 'OUT command: ' + statusName(-6)) failures.push('a negative stiffness: ' + refused);
if (states === 0 || commands === 0 || features < 8) failures.push('too few state, command or feature vectors seen: ' + [states, commands, features]);
if (failures.length) {
  console.error(failures.join('\n'));
  process.exit(1);
}
console.log(count + ' golden vectors agree with the wasm codec; ' + states + ' state vectors through decodeState, ' + commands + ' command vectors through encodeCommand; ' + features + ' feature vectors through decodeFeature/encodeFeature');

// protocol/'s codec compiled to WebAssembly (cathbox-protocol.js) and its JavaScript face
// (host/server/web/js/box_codec.js) against the golden vectors (protocol/vectors), under node:
//  - every vector through the wasm build's own cbx_vector_decode/encode (good ones round trip
//    byte for byte, bad ones are refused with their status);
//  - every good state vector's bytes decoded by BoxCodec.decodeState to the vector's value,
//    field by field; every bad state vector refused with its status's name;
//  - every good command vector's value encoded by BoxCodec.encodeCommand to its bytes.
//   node protocol_codec_test.mjs build/wasm/bin/cathbox-protocol.js host/server/web/js/box_codec.js
import { createRequire } from 'module';
import { pathToFileURL } from 'url';
import path from 'path';

const [modulePath, codecPath] = process.argv.slice(2);
const require = createRequire(import.meta.url);
const CathboxProtocol = require(path.resolve(modulePath));
const { BoxCodec, STATE_FIELDS } = await import(pathToFileURL(path.resolve(codecPath)).href);

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
  }
}
let refused = null;
try {
  codec.encodeCommand({ seq: 1, mode: 1, insertion: { offset: 0, pos0: 0, stiffness: -1, damping: 0, out_min: 0, out_max: 0 },
    rotation: { offset: 0, pos0: 0, stiffness: 0, damping: 0, out_min: 0, out_max: 0 } });
} catch (e) { refused = e.message; }
if (refused !== 'OUT command: ' + statusName(-6)) failures.push('a negative stiffness: ' + refused);
if (states === 0 || commands === 0) failures.push('no state or command vector seen');
if (failures.length) {
  console.error(failures.join('\n'));
  process.exit(1);
}
console.log(count + ' golden vectors agree with the wasm codec; ' + states + ' state vectors through decodeState, ' + commands + ' command vectors through encodeCommand');

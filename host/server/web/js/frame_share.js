// The haptic worker's frame for the trainee page, in one preallocated SharedArrayBuffer instead
// of a message a frame (js/train_worker.js writes, js/train.js reads on its animation frame): the
// worker's steady state copies into memory it already has and allocates nothing, and the
// renderer's allocator and message queue see none of it (docs/wasm/haptic-clock.md, "Shared
// frame"). A seqlock: the writer makes the sequence odd, writes, makes it even; the reader copies
// out and keeps the copy only if the sequence was even and unchanged across it (else it reads the
// next one on its next frame). Rare things stay messages: the fluoroscopy's phantom and scenes
// when new, the box's report, start, end, errors.
//
// Layout: Int32 head [seq, floats, metrics bytes, drive bytes, fluoro (0/1), float capacity, byte
// capacity]; Float64 [lateMs, fluoro header (56), C-arm (9)]; Float32 snapshot floats; Uint8
// metrics JSON then drive JSON (UTF-8, as the module's strings).
const HEAD = 16;
export const HEADER_DOUBLES = 56;
const CARM = 9;
const DOUBLES = 1 + HEADER_DOUBLES + CARM;
const F64_AT = HEAD * 4;
const F32_AT = F64_AT + DOUBLES * 8;

export class SharedFrame {
  // A new frame buffer for up to `floats` snapshot floats and `bytes` of each JSON text.
  static create(floats, bytes) {
    const frame = new SharedFrame(new SharedArrayBuffer(F32_AT + floats * 4 + 2 * bytes), floats, bytes);
    frame.head[5] = floats;
    frame.head[6] = bytes;
    return frame;
  }

  // The page's view of the worker's buffer (its capacities read from it).
  static attach(buffer) {
    const head = new Int32Array(buffer, 0, HEAD);
    return new SharedFrame(buffer, head[5], head[6]);
  }

  constructor(buffer, floats, bytes) {
    this.buffer = buffer;
    this.head = new Int32Array(buffer, 0, HEAD);
    this.f64 = new Float64Array(buffer, F64_AT, DOUBLES);
    this.f32 = new Float32Array(buffer, F32_AT, floats);
    this.metrics = new Uint8Array(buffer, F32_AT + floats * 4, bytes);
    this.drive = new Uint8Array(buffer, F32_AT + floats * 4 + bytes, bytes);
    this.seen = 0;  // the reader's last sequence taken
  }

  fits(floats, metricsBytes, driveBytes) {
    return floats <= this.f32.length && metricsBytes <= this.metrics.length && driveBytes <= this.drive.length;
  }

  // The writer: fill(frame) writes f32, f64, metrics, drive and returns [floats, metrics bytes,
  // drive bytes, fluoro 0/1] through the head (setCounts) between the odd and the even sequence.
  begin() { Atomics.add(this.head, 0, 1); }
  setCounts(floats, metricsBytes, driveBytes, fluoro) {
    this.head[1] = floats;
    this.head[2] = metricsBytes;
    this.head[3] = driveBytes;
    this.head[4] = fluoro;
  }
  end() { Atomics.add(this.head, 0, 1); }
}

// The page's side: copies of the newest whole frame, into arrays made once.
export class FrameReader {
  constructor(buffer) {
    this.shared = SharedFrame.attach(buffer);
    const s = this.shared;
    this.f32 = new Float32Array(s.f32.length);
    this.f64 = new Float64Array(s.f64.length);
    this.metrics = new Uint8Array(s.metrics.length);  // TextDecoder takes no shared view
    this.drive = new Uint8Array(s.drive.length);
    this.decoder = new TextDecoder();
  }

  // The newest frame not yet taken, or null (none new, or the worker was writing it).
  take() {
    const s = this.shared;
    const seq = Atomics.load(s.head, 0);
    if (seq & 1 || seq === s.seen) return null;
    const [n, mb, db, fluoro] = [s.head[1], s.head[2], s.head[3], s.head[4]];
    if (!(n <= this.f32.length && mb <= this.metrics.length && db <= this.drive.length)) return null;
    this.f32.set(s.f32.subarray(0, n));
    this.f64.set(s.f64);
    this.metrics.set(s.metrics.subarray(0, mb));
    this.drive.set(s.drive.subarray(0, db));
    if (Atomics.load(s.head, 0) !== seq) return null;
    s.seen = seq;
    return {
      data: this.f32.subarray(0, n),
      metricsText: this.decoder.decode(this.metrics.subarray(0, mb)),
      driveText: this.decoder.decode(this.drive.subarray(0, db)),
      lateMs: this.f64[0],
      fluoro: fluoro ? { header: this.f64.slice(1, 1 + HEADER_DOUBLES), carm: this.f64.slice(1 + HEADER_DOUBLES) } : null,
    };
  }
}

// The box driving the trainee page's session, as BoxClient and BoxHand do for the native trainer.
// The driver lives in the haptic worker (js/train_worker.js), over either transport (the bridge or
// WebHID, js/box_transport.js): its reports and commands are handled between the worker's tick
// slices (at most 8 ms apart), so commands keep well inside the box's 50 ms watchdog whatever the
// page's thread is doing (drawing under software GL stalls it for 50-350 ms). The speeds written
// here are read from shared memory each tick. Every byte goes through protocol/'s codec compiled to
// wasm (js/box_codec.js). What it does:
//   - each IN (state) report: decoded (a refused one is counted with its status, never used),
//     sequence gaps counted; the encoders' counts -> the box's insertion (mm) and rotation (rad)
//     from where they were when the box connected;
//   - the held tool follows the box: the session takes speeds, so the page sends it
//     (box - tool) / 50 ms (bounded), a position servo on the speed input;
//   - the force law: every 5 ms at most (the box's command watchdog is 50 ms), the held tool's
//     local force law — offset, position, stiffness and damping — shaped and encoded by the
//     session module in the haptic worker (cbx_box_command: session::PassiveLaw and
//     device::force_law_command, the native BoxHand's own path, so the same law gives the same
//     bytes), in the box's frame (the counts' zero), with the box's readback (rendered force,
//     speed) for the passivity observer; ACK_FAULTS while a fault is latched (the watchdog fault
//     a box latches before the first command);
//   - outputs off when the run ends or the page goes.
//   - on connect, the box's device info, calibration and limits (feature reports, over WebHID or
//     through the bridge), as BoxClient and BoxHand do: a box of another protocol version or one
//     not calibrated is refused with one line (the keyboard stays); the calibration converts the
//     counts, the smaller of the limits' and the calibration's full scale bounds the law, and a
//     motor box is driven in motor mode (BoxHand's choice). A transport without feature reports
//     would get the reference box's figures (hw-sim/README.md: 108 650 counts/m, 4096
//     counts/rev); report().config says which.
import { BoxCodec, FEATURE } from './box_codec.js';

export const INSERTION_COUNTS_PER_M = 108650;
export const ROTATION_COUNTS_PER_REV = 4096;
const MODE_OFF = 0;
const MODE_BRAKE = 1;
const MODE_MOTOR = 2;
const ACTUATOR_MOTOR = 2;
const ACK_FAULTS = 1;
const FAULT_NOT_CALIBRATED = 1 << 4;
const FOLLOW_S = 0.05;
const MAX_MM_S = 200;
const MAX_RAD_S = 20;
export const SEND_MS = 5;
const FULL_SCALE_mN = 5000;
const FULL_SCALE_uNm = 50000;
const SLEW_mN_PER_ms = 100;  // the firmware's default limits

let codecPromise = null;

// cathbox-protocol.js from the server's /wasm/ (a classic script defining CathboxProtocol), in the
// haptic worker (a classic worker).
function loadCodec() {
  if (!codecPromise) {
    try {
      importScripts('/wasm/cathbox-protocol.js');
    } catch (_) {
      return Promise.reject(new Error('/wasm/cathbox-protocol.js: the box codec is not served here (cathbox-server --wasm DIR)'));
    }
    codecPromise = self.CathboxProtocol({ locateFile: (p) => '/wasm/' + p, mainScriptUrlOrBlob: '/wasm/cathbox-protocol.js' }).then((m) => new BoxCodec(m));
  }
  return codecPromise;
}

const clamp = (v, lo, hi) => Math.min(hi, Math.max(lo, v));

export class BoxDriver {
  // keys: the Float64Array the worker reads (mm/s, rad/s); sessionAt(): the newest frame's
  // {insertion_mm, rotation_rad, hand_force_mN, torque_mNmm} or null; onChange(text) for the page;
  // law: the session's command maker, {configure(config), command({seq, time_us, flags,
  // offset_mm, offset_rad, force_mN, speed_mm_s}) -> bytes or a promise of them} (js/train_worker.js).
  constructor({ keys, sessionAt, onChange, law }) {
    this.keys = keys;
    this.law = law;
    this.sessionAt = sessionAt;
    this.onChange = onChange;
    this.seq = 0;
    this.lastSentAt = -Infinity;
    this.zero = null;
    this.stats = { states: 0, missed: 0, rejected: 0, last_rejected: '', sent: 0, dropped: 0, max_send_gap_ms: 0 };
    this.state = null;
    this.live = false;
  }

  async connect(transport) {
    this.codec = await loadCodec();
    this.transport = transport;
    transport.onReport = (bytes) => { if (this.live) this.onReport(bytes); };
    transport.onClose = (reason) => this.lost(reason);
    await transport.open();
    try {
      this.config = await this.readConfig(transport);
    } catch (err) {
      transport.close('refused');
      throw err;
    }
    this.law.configure(this.config);
    this.live = true;
    this.onChange('box: ' + transport.describe() + ' (waiting for its first report)');
  }

  // What the box says of itself (feature reports 0x10-0x12, through protocol/'s codec), or the
  // reference box's figures for a transport without feature reports.
  async readConfig(transport) {
    if (!transport.feature) {
      return { source: 'reference box (the transport carries no feature report)', insertion_counts_per_m: INSERTION_COUNTS_PER_M,
        rotation_counts_per_rev: ROTATION_COUNTS_PER_REV, full_scale_mN: FULL_SCALE_mN, full_scale_uNm: FULL_SCALE_uNm,
        slew_mN_per_ms: SLEW_mN_PER_ms, mode: MODE_BRAKE };
    }
    const info = this.codec.decodeFeature(FEATURE.device_info, await transport.feature(FEATURE.device_info));
    const cal = this.codec.decodeFeature(FEATURE.calibration, await transport.feature(FEATURE.calibration));
    if (!cal.insertion_counts_per_m || !cal.rotation_counts_per_rev) throw new Error(transport.describe() + " is not calibrated (run 'cathbox calibrate')");
    const limits = this.codec.decodeFeature(FEATURE.limits, await transport.feature(FEATURE.limits));
    return { source: 'the box', serial: info.serial, board: info.board, firmware: info.fw_major + '.' + info.fw_minor + '.' + info.fw_patch,
      insertion_counts_per_m: cal.insertion_counts_per_m, rotation_counts_per_rev: cal.rotation_counts_per_rev,
      full_scale_mN: Math.min(limits.max_force_mN, cal.insertion_full_scale_mN),
      full_scale_uNm: Math.min(limits.max_torque_uNm, cal.rotation_full_scale_uNm), slew_mN_per_ms: limits.force_slew_mN_per_ms,
      watchdog_ms: limits.watchdog_timeout_ms, mode: info.insertion_actuator === ACTUATOR_MOTOR ? MODE_MOTOR : MODE_BRAKE };
  }

  onReport(bytes) {
    let s;
    try {
      s = this.codec.decodeState(bytes);
    } catch (err) {
      this.stats.rejected++;
      this.stats.last_rejected = err.message;
      return;
    }
    if (this.state && ((s.seq - this.state.seq) & 0xffff) > 1) this.stats.missed += ((s.seq - this.state.seq) & 0xffff) - 1;
    this.state = s;
    this.stats.states++;
    const got = performance.now();
    if (this.lastReportAt !== undefined) this.stats.max_report_gap_ms = Math.max(this.stats.max_report_gap_ms || 0, got - this.lastReportAt);
    this.lastReportAt = got;
    const at = this.sessionAt();
    if (!at) return;
    if (!this.zero) {
      this.zero = { insertion_count: s.insertion_count, rotation_count: s.rotation_count, insertion_mm: at.insertion_mm, rotation_rad: at.rotation_rad };
      this.onChange('box: ' + this.transport.describe() + ' drives the held tool');
    }
    const c = this.config;
    this.box_mm = this.zero.insertion_mm + (s.insertion_count - this.zero.insertion_count) * 1000 / c.insertion_counts_per_m;
    this.box_rad = this.zero.rotation_rad + (s.rotation_count - this.zero.rotation_count) * 2 * Math.PI / c.rotation_counts_per_rev;
    this.keys[0] = clamp((this.box_mm - at.insertion_mm) / FOLLOW_S, -MAX_MM_S, MAX_MM_S);
    this.keys[1] = clamp((this.box_rad - at.rotation_rad) / FOLLOW_S, -MAX_RAD_S, MAX_RAD_S);
    const now = performance.now();
    if (now - this.lastSentAt >= SEND_MS) {
      if (this.lastSentAt > 0) this.stats.max_send_gap_ms = Math.max(this.stats.max_send_gap_ms, now - this.lastSentAt);
      this.lastSentAt = now;
      this.sendLaw(at, s);
    }
  }

  // Outputs off (the law's fields all zero).
  offCommand() {
    const law = { offset: 0, pos0: 0, stiffness: 0, damping: 0, out_min: 0, out_max: 0 };
    return this.codec.encodeCommand({ seq: this.seq, time_us: Math.round(performance.now() * 1000) >>> 0, mode: MODE_OFF, flags: 0,
      insertion: law, rotation: law });
  }

  // The held tool's law in the box's frame: the box's position from its counts' zero is the
  // session's plus (zero count / calibration - the session's position at the zero).
  sendLaw(at, s) {
    const c = this.config;
    const seq = this.seq;
    this.seq = (this.seq + 1) & 0xffff;
    const made = this.law.command({
      seq, time_us: Math.round(performance.now() * 1000) >>> 0, flags: (s.faults & ~FAULT_NOT_CALIBRATED) ? ACK_FAULTS : 0,
      offset_mm: this.zero.insertion_count * 1000 / c.insertion_counts_per_m - this.zero.insertion_mm,
      offset_rad: this.zero.rotation_count * 2 * Math.PI / c.rotation_counts_per_rev - this.zero.rotation_rad,
      force_mN: s.insertion_force_mN, speed_mm_s: s.insertion_vel_cps * 1000 / c.insertion_counts_per_m,
    });
    const send = (bytes) => {
      if (!this.live) return;
      if (this.transport.send(bytes)) this.stats.sent++; else this.stats.dropped++;
      const sent = this.codec.decodeCommand(bytes);
      this.lastLaw = { seq: sent.seq, mode: sent.mode, insertion: sent.insertion, rotation: sent.rotation,
        insertion_offset_mN: sent.insertion.offset, rotation_offset_uNm: sent.rotation.offset };
    };
    if (made instanceof Promise) made.then(send, (err) => { this.stats.dropped++; this.stats.last_law_error = err.message; });
    else send(made);
  }

  // Outputs off, then the link closed (end of run, page closed).
  stop() {
    if (!this.live) return;
    this.live = false;
    this.transport.send(this.offCommand());
    this.transport.close('run over');
    this.keys[0] = 0;
    this.keys[1] = 0;
  }

  // The link closed: said only if it was driving (not after stop() or a refused connect).
  lost(reason) {
    if (!this.live) return;
    this.live = false;
    this.keys[0] = 0;
    this.keys[1] = 0;
    this.onChange('box lost: ' + reason + ' (the tool stops; the keyboard drives it)');
  }

  // What tests and the HUD read.
  report() {
    const s = this.state;
    return { live: this.live, config: this.config || null, box_mm: this.box_mm, box_rad: this.box_rad, stats: { ...this.stats }, law: this.lastLaw || null,
      state: s ? { seq: s.seq, insertion_count: s.insertion_count, rotation_count: s.rotation_count, status: s.status, faults: s.faults,
        mode: s.mode, command_seq_echo: s.command_seq_echo, insertion_force_mN: s.insertion_force_mN,
        insertion_current_mA: s.insertion_current_mA, rx_errors: s.rx_errors } : null };
  }
}

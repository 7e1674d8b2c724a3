// The trainee page's live stream to instructors, as cathbox-trainer's (host/app ServerLink):
// a publisher WebSocket on /api/v1/live/rigs/RIG/stream?case=NAME[&version=V][&assignment=ID]
// (the token as the subprotocol `bearer.TOKEN`, since a browser cannot set the header), frames
// of live_schema.hpp at most every 33 ms with one in flight, {"type":"end"} when the run ends.
// A refused or lost stream never stops the run: the page says so on its status line.
import { token } from './api.js';

const FRAME_MS = 33;
const MAX_NODES = 1024;  // live_schema.hpp kMaxNodesPerTool
const MAX_CONTACTS = 256;

const round = (v) => Math.round(v * 1000) / 1000;
const vec = (p) => [round(p[0]), round(p[1]), round(p[2])];

// At most MAX_NODES nodes: every k-th, and always the tip (as frame_json does).
function nodeList(flat) {
  const n = flat.length / 3;
  const step = Math.ceil(n / MAX_NODES) || 1;
  const out = [];
  for (let i = 0; i < n; i += step) if (i + 1 < n || step <= 1) out.push(vec(flat.subarray(3 * i, 3 * i + 3)));
  if (step > 1 && n > 0) out.push(vec(flat.subarray(3 * (n - 1), 3 * n)));
  return out;
}

export class LiveRig {
  // onState(text): the stream's state for the page's status line.
  constructor({ rig, caseName, version, assignment, toolNames, onState }) {
    const q = new URLSearchParams({ case: caseName });
    if (version !== 'latest') q.set('version', version);
    if (assignment) q.set('assignment', String(assignment));
    const scheme = location.protocol === 'https:' ? 'wss://' : 'ws://';
    this.rig = rig;
    this.toolNames = toolNames;
    this.seq = 0;
    this.lastAt = -Infinity;
    this.onState = onState;
    this.ws = new WebSocket(scheme + location.host + '/api/v1/live/rigs/' + encodeURIComponent(rig) + '/stream?' + q,
      ['cathbox', 'bearer.' + token()]);
    this.ws.onopen = () => onState('live as ' + rig);
    this.ws.onclose = (e) => { if (!this.ended) onState('live stream closed (' + (e.reason || e.code) + ')'); };
  }

  // A snapshot (train.js unpack) and its metrics; sent when the socket is free and 33 ms passed.
  frame(s, metrics, force = false) {
    const now = performance.now();
    if (this.ws.readyState !== WebSocket.OPEN || this.ws.bufferedAmount > 0 || (!force && now - this.lastAt < FRAME_MS)) return false;
    this.lastAt = now;
    const frame = {
      type: 'frame', seq: ++this.seq, t_ms: round(s.time_s * 1000),
      tools: s.tools.slice(0, 8).map((t, i) => ({ name: this.toolNames[i] || 'tool' + i, active: t.active, nodes_mm: nodeList(t.nodes) })),
      tip_mm: vec(s.tip), forces: { hand_mN: round(s.hand_force_mN), wall_peak_mN: round(s.wall_force_mN) },
      contacts: s.contacts.slice(0, MAX_CONTACTS).map((c) => ({ p_mm: vec(c.p_mm), f_mN: round(c.f_mN) })),
      metrics, sent_us: Math.round((performance.timeOrigin + now) * 1000),
    };
    this.ws.send(JSON.stringify(frame));
    return true;
  }

  end() {
    this.ended = true;
    this.onState('live stream ended (' + this.seq + ' frames)');
    if (this.ws.readyState === WebSocket.OPEN) this.ws.send('{"type":"end"}');
    this.ws.close(1000);
  }
}

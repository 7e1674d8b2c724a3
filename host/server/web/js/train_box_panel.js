// The trainee page's box panel: the box the address or the browser offers (the page's only part in
// driving it: Chromium's WebHID chooser needs a click; the haptic worker drives it, js/train_box.js),
// the notes on it, and its figures under the keys as the worker reports them (train.js passes them on).
import { guarded } from './api.js';
import { askForBox, chooseBox } from './box_transport.js';

export function boxNote(text) { document.getElementById('box-note').textContent = text; }

// The box the address or the browser offers (js/box_transport.js); the keyboard until it is up.
// Either way the haptic worker drives it (js/train_worker.js): the page only asks Chromium for the
// WebHID box (the chooser needs a click here; `openHid` then tells the worker) and shows the
// figures the worker's frames carry. `run.boxUrl`: the bridge's address, for the worker's open.
export function offerBox(params, run, openHid) {
  const choice = chooseBox(params);
  if (!choice.kind) return boxNote(choice.why);
  if (choice.kind === 'bridge') {
    run.boxUrl = choice.url;
    return boxNote('box: the box bridge at ' + choice.url + ' (connecting from the haptic worker)');
  }
  boxNote('The keyboard drives the tool until a box is connected.');
  const button = document.getElementById('connect-box');
  button.hidden = false;
  button.onclick = () => guarded(async () => {
    button.hidden = true;
    let name = null;
    try {
      name = await askForBox();
    } catch (err) {
      return boxNote('no box: WebHID: ' + err.message + ' (the keyboard drives the tool)');
    }
    if (!name) {
      button.hidden = false;
      return boxNote('no box: none chosen (the keyboard drives the tool)');
    }
    boxNote('box: WebHID ' + name + ' (connecting from the haptic worker)');
    openHid();
  });
}

// The box's figures under the keys: its position, the page's decoding and command stream, the
// last force law sent and the box's own state (protocol/README.md's status bits, its command echo);
// and what the box said of itself on connect (its feature reports: device info, calibration,
// limits) or that the reference box's figures stand in for them.
export function showBoxReport(r) {
  if (!r) return;
  const s = r.state;
  const law = r.law;
  const st = r.stats || {};
  const line = document.getElementById('box-report');
  if (!s) {  // nothing from a box yet: said, not a line of blanks
    line.textContent = r.live ? 'Box connected: waiting for its first report.' : 'No box connected: the keyboard drives the tool.';
  } else {
    line.textContent =
      `box ${(r.box_mm ?? 0).toFixed(3)} mm ${(r.box_rad ?? 0).toFixed(4)} rad; states ${st.states}, missed ${st.missed}, rejected ${st.rejected}, ` +
      `longest report gap ${(st.max_report_gap_ms ?? 0).toFixed(3)} ms, longest command gap ${(st.max_send_gap_ms ?? 0).toFixed(3)} ms; ` +
      (law ? `law seq ${law.seq}, offset ${law.insertion_offset_mN} mN` : 'no law sent yet') + `; box status 0x${s.status.toString(16)}, ` +
      `faults ${s.faults}, mode ${s.mode}, rx errors ${s.rx_errors}, command echo ${s.command_seq_echo}, ` +
      `force ${s.insertion_force_mN} mN`;
  }
  const c = r.config;
  if (!c) return;
  const who = c.source === 'the box' ? `${c.board} ${c.serial}, firmware ${c.firmware}` : c.source;
  document.getElementById('box-config').textContent = `Box: ${who}; ${c.insertion_counts_per_m} counts/m, ${c.rotation_counts_per_rev} counts/rev, ` +
    `full scale ${c.full_scale_mN} mN, ${c.full_scale_uNm} µN·m, slew ${c.slew_mN_per_ms} mN/ms, ${c.mode === 2 ? 'motor' : 'brake'} mode`;
}

// The trainee page's snapshot as the worker sends it, and what the page writes of it: the
// floats unpacked, the HUD's lines, the nodes thinned for the views (train.js draws them).

// Snapshot floats (host/wasm browser_session.cpp): the header, the tools, the contacts.
export function unpack(d) {
  const s = {
    tick: d[0], time_s: d[1], insertion_mm: d[2], rotation_rad: d[3], hand_force_mN: d[4], torque_mNmm: d[5],
    wall_force_mN: d[6], tip: [d[7], d[8], d[9]], held: d[10], over: d[11] > 0, tools: [], contacts: [],
  };
  let i = 14;
  for (let t = 0; t < d[12]; ++t) {
    const n = d[i];
    s.tools.push({ active: d[i + 1] > 0, nodes: d.subarray(i + 2, i + 2 + 3 * n) });
    i += 2 + 3 * n;
  }
  for (let c = 0; c < d[13]; ++c, i += 4) s.contacts.push({ p_mm: [d[i], d[i + 1], d[i + 2]], f_mN: d[i + 3] });
  return s;
}

// The HUD: `run` the open run (caseName, tools, drive), `virtualClock` whether ticks run on demand.
export function hudText(s, run, virtualClock) {
  const tool = run.tools[s.held] || '?';
  return [
    run.caseName + '  ' + (virtualClock ? '(virtual clock)' : ''),
    'time      ' + s.time_s.toFixed(3) + ' s',
    'tool      ' + tool,
    'insertion ' + s.insertion_mm.toFixed(2) + ' mm',
    'rotation  ' + s.rotation_rad.toFixed(3) + ' rad',
    'hand      ' + s.hand_force_mN.toFixed(1) + ' mN  ' + s.torque_mNmm.toFixed(2) + ' mN·mm',
    'wall      ' + s.wall_force_mN.toFixed(1) + ' mN',
    ...run.drive.hints,  // the stent retriever's U and E (app::DeviceDrive::hints), its last note
    ...(run.drive.note ? [run.drive.note] : []),
  ].join('\n');
}

// At most `max` nodes of a flat [x,y,z,...] list: every k-th, and always the tip (the views draw
// 256 nodes a tool; a longer tool would otherwise lose its distal end).
export function fit(flat, max = 256) {
  const n = flat.length / 3;
  if (n <= max) return flat;
  const step = Math.ceil((n - 1) / (max - 1));
  const out = [];
  for (let i = 0; i < n - 1; i += step) out.push(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  out.push(flat[3 * n - 3], flat[3 * n - 2], flat[3 * n - 1]);
  return out;
}

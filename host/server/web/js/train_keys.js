// The native trainer's key table (host/app/src/input_controller.cpp), by KeyboardEvent.code:
// W/Up push and S/Down pull at 10 mm/s, A/Left and D/Right twist at +/-1.5 rad/s, Shift x4;
// Tab the next tool, C frames the camera, F wireframe, Escape ends the run; a stent retriever's U
// (unsheathe) and E (retrieve), decided in the worker by cathbox-trainer's DeviceDrive; the fluoroscopy's
// Space (pedal), I (inject), R (roadmap), X (clear it), [ ] - = (the C-arm: RAO, LAO, caudal,
// cranial), held as bits in session::FluoroKeys' order (host/wasm browser_session.hpp).
const PUSH = ['KeyW', 'ArrowUp'];
const PULL = ['KeyS', 'ArrowDown'];
const LEFT = ['KeyA', 'ArrowLeft'];
const RIGHT = ['KeyD', 'ArrowRight'];
const SHIFT = ['ShiftLeft', 'ShiftRight'];
const ACTIONS = ['Tab', 'Escape', 'KeyC', 'KeyF', 'KeyU', 'KeyE'];
const FLUORO = ['Space', 'KeyI', 'KeyR', 'KeyX', 'BracketLeft', 'BracketRight', 'Minus', 'Equal'];
const ALL = new Set([...PUSH, ...PULL, ...LEFT, ...RIGHT, ...SHIFT, ...ACTIONS, ...FLUORO]);

export function isControlKey(code) { return ALL.has(code); }

// The fluoroscopy keys held as bits (pedal 1, inject 2, roadmap 4, clear 8, RAO 16, LAO 32,
// caudal 64, cranial 128).
export function fluoroBits(held) {
  return FLUORO.reduce((bits, code, i) => (held.has(code) ? bits | (1 << i) : bits), 0);
}

// An arrow or WASD key held (it stops a stent drive, as in cathbox-trainer).
export function steering(held) {
  return [...PUSH, ...PULL, ...LEFT, ...RIGHT].some((c) => held.has(c));
}

// [insertion mm/s, rotation rad/s] for the set of codes held.
export function speedsFor(held) {
  const any = (codes) => codes.some((c) => held.has(c));
  const fast = any(SHIFT) ? 4 : 1;
  let insert = 0;
  let twist = 0;
  if (any(PUSH)) insert += 10 * fast;
  if (any(PULL)) insert -= 10 * fast;
  if (any(LEFT)) twist += 1.5 * fast;
  if (any(RIGHT)) twist -= 1.5 * fast;
  return [insert, twist];
}

#!/usr/bin/env bash
# The WebAssembly session (host/wasm, run by node) against the native one, on bundled cases:
#  - the vessel surface meshed natively (`cathbox vessel mesh -o FILE.cbxmesh`) is what the wasm
#    session builds its collision tree from;
#  - a wasm run of a case from an action script (push, a full turn of the tip, push) writes a
#    record that `cathbox session replay --check` replays natively with every state hash
#    matching, and both records give the same metrics;
#  - a native record replays in wasm with every hash;
#  - a wrong surface makes the replay differ (exit 1), a truncated mesh is one line (exit 2).
# Usage: wasm_session_test.sh CATHBOX SOURCE_DIR WORK_DIR SESSION_JS
source "$(dirname "${BASH_SOURCE[0]}")/../cli/cli_check.sh"
js="$4"
cb="$cathbox"
cases="$src/cases"
wasm() { node --no-experimental-fetch "$js" "$@"; }
matches() { grep -q "every state hash matches" "$work/out" || fail "$1: $(cat "$work/out")"; }

# CASE:ACTIONS:RUN. The third, a keyboard-like run (push 40 mm at 40 mm/s, a full turn at
# 344 deg/s, push at 10 mm/s), puts the tip into a crease of the Y's mesh where two faces report
# the same edge: the collision tree kept whichever it offered first, which differs between the
# builds (float bounds), and the runs split at tick 4842 (state hash differs at tick 4899).
for triple in y_bifurcation:y_bifurcation_left.actions:y_bifurcation neuro_aneurysm::neuro_aneurysm \
              y_bifurcation:keyboard:y_keyboard; do
  name=${triple%%:*}
  rest=${triple#*:}
  actions=${rest%%:*}
  run=${rest#*:}
  if [ -z "$actions" ]; then
    actions="$work/push.actions"
    printf '0 insert_to 40 at 30\n1400 rotate_to 360 at 180\n2500 insert_to 90 at 20\n4000 end\n' >"$actions"
  elif [ "$actions" = keyboard ]; then
    actions="$work/keyboard.actions"
    printf '0 insert_to 40 at 40\n1000 rotate_to 360 at 344\n2050 insert_to 95 at 10\n6000 end\n' >"$actions"
  else
    actions="$cases/$actions"
  fi
  vessel=$(sed -n 's/^vessel[[:space:]]\{1,\}//p' "$cases/$name.case" | head -1)
  mesh="$work/$name.cbxmesh"
  [ -f "$mesh" ] || expect 0 "$cb" vessel mesh "$cases/$vessel" -o "$mesh"
  # wasm run -> native replay
  expect 0 wasm run --case "$cases/$name.case" --mesh "$mesh" --script "$actions" --record "$work/$run.wasm.cbxrec"
  expect 0 "$cb" session replay "$work/$run.wasm.cbxrec" --check
  matches "$run: native replay of the wasm record"
  # native run -> wasm replay
  expect 0 "$cb" session run --case "$cases/$name.case" --script "$actions" --virtual --record "$work/$run.native.cbxrec"
  expect 0 wasm replay "$work/$run.native.cbxrec" --mesh "$mesh" --check
  matches "$run: wasm replay of the native record"
  # The same run: every metric of the two records, replayed natively, is the same.
  "$cb" session metrics "$work/$run.wasm.cbxrec" >"$work/wasm.metrics" 2>&1
  "$cb" session metrics "$work/$run.native.cbxrec" >"$work/native.metrics" 2>&1
  grep -q "procedure time" "$work/native.metrics" || fail "$run: metrics: $(cat "$work/native.metrics")"
  cmp -s "$work/wasm.metrics" "$work/native.metrics" && echo "ok:   $run: the same metrics from both records" \
    || fail "$run: the metrics differ: $(diff "$work/wasm.metrics" "$work/native.metrics" | head -5)"
done

# A surface that is not the record's vessel's: the physics differs, --check says where (exit 1).
expect 1 wasm replay "$work/y_bifurcation.native.cbxrec" --mesh "$work/neuro_aneurysm.cbxmesh" --check
grep -q "state hash differs at tick" "$work/out" || fail "wrong surface: $(cat "$work/out")"
# A truncated mesh: one line naming the file and the byte, exit 2.
head -c 1000 "$work/y_bifurcation.cbxmesh" >"$work/short.cbxmesh"
expect 2 wasm replay "$work/y_bifurcation.native.cbxrec" --mesh "$work/short.cbxmesh" --check
[ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "short.cbxmesh: byte 1000: truncated" "$work/err" || fail "truncated mesh: $(cat "$work/err")"
finish wasm_session

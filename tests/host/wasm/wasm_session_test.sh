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

for pair in y_bifurcation:y_bifurcation_left.actions neuro_aneurysm:; do
  name=${pair%%:*}
  actions=${pair#*:}
  if [ -z "$actions" ]; then
    actions="$work/push.actions"
    printf '0 insert_to 40 at 30\n1400 rotate_to 360 at 180\n2500 insert_to 90 at 20\n4000 end\n' >"$actions"
  else
    actions="$cases/$actions"
  fi
  vessel=$(sed -n 's/^vessel[[:space:]]\{1,\}//p' "$cases/$name.case" | head -1)
  mesh="$work/$name.cbxmesh"
  expect 0 "$cb" vessel mesh "$cases/$vessel" -o "$mesh"
  # wasm run -> native replay
  expect 0 wasm run --case "$cases/$name.case" --mesh "$mesh" --script "$actions" --record "$work/$name.wasm.cbxrec"
  expect 0 "$cb" session replay "$work/$name.wasm.cbxrec" --check
  matches "$name: native replay of the wasm record"
  # native run -> wasm replay
  expect 0 "$cb" session run --case "$cases/$name.case" --script "$actions" --virtual --record "$work/$name.native.cbxrec"
  expect 0 wasm replay "$work/$name.native.cbxrec" --mesh "$mesh" --check
  matches "$name: wasm replay of the native record"
  # The same run: every metric of the two records, replayed natively, is the same.
  "$cb" session metrics "$work/$name.wasm.cbxrec" >"$work/wasm.metrics" 2>&1
  "$cb" session metrics "$work/$name.native.cbxrec" >"$work/native.metrics" 2>&1
  grep -q "procedure time" "$work/native.metrics" || fail "$name: metrics: $(cat "$work/native.metrics")"
  cmp -s "$work/wasm.metrics" "$work/native.metrics" && echo "ok:   $name: the same metrics from both records" \
    || fail "$name: the metrics differ: $(diff "$work/wasm.metrics" "$work/native.metrics" | head -5)"
done

# A surface that is not the record's vessel's: the physics differs, --check says where (exit 1).
expect 1 wasm replay "$work/y_bifurcation.native.cbxrec" --mesh "$work/neuro_aneurysm.cbxmesh" --check
grep -q "state hash differs at tick" "$work/out" || fail "wrong surface: $(cat "$work/out")"
# A truncated mesh: one line naming the file and the byte, exit 2.
head -c 1000 "$work/y_bifurcation.cbxmesh" >"$work/short.cbxmesh"
expect 2 wasm replay "$work/y_bifurcation.native.cbxrec" --mesh "$work/short.cbxmesh" --check
[ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "short.cbxmesh: byte 1000: truncated" "$work/err" || fail "truncated mesh: $(cat "$work/err")"
finish wasm_session

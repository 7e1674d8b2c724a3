#!/usr/bin/env bash
# `cathbox session run|replay|metrics|info` end to end, for every bundled case:
#  - driven by an action script in virtual time, then replayed with every state hash checked
#    (`metrics`, which refuses a record whose replay differs);
#  - against a real `cathbox-emu` process in real time (its scripted hand pushes and twists the
#    wire), then replayed the same way;
#  - a run killed with SIGKILL mid-way leaves a record that reads and replays to its last block;
#  - neuro under fluoroscopy by script (pedal, injection, roadmap): the figures printed, in the
#    JSON and replayed; a bad imaging verb or value is one line with file:line, exit 2;
#  - a changed, truncated or foreign record is one line and exit 2 (replay --check: exit 1 with
#    the first differing tick when the inputs no longer give the recorded states).
# No sleeps: the emulator is awaited by its "listening" line, the killed run by its "recorded"
# progress lines; no timing is asserted.
# Usage: session_cli_test.sh BIN_DIR CASES_DIR [quick]
source "$(dirname "${BASH_SOURCE[0]}")/session_cli_lib.sh"
quick="${3:-}"

# A push, a full turn of the tip and a further push: every case's wire meets a wall and a branch.
cat >"$work/push.actions" <<'EOF'
0     insert_to 40 at 30
1400  rotate_to 360 at 180
2500  insert_to 90 at 20
5000  end
EOF

for c in "$cases"/*.case; do
  name=$(basename "$c" .case)
  rec="$work/$name.cbxrec"
  expect 0 "$cb" session run --case "$c" --script "$work/push.actions" --virtual --record "$rec" || continue
  grep -q "end of run" "$work/out" || fail "$name: no end-of-run line"
  # `metrics` replays the record with every state hash checked (a differing one: exit 1), as
  # `replay --check` does; that command's own output is checked on the records below.
  expect 0 "$cb" session metrics "$rec" --json
  shape session-metrics
  jq -e '.tip_path_mm > 10' "$work/out" >/dev/null || fail "$name: metrics: $(head -c 300 "$work/out")"
  expect 0 "$cb" session info "$rec" --json
  shape session-info
  jq -e '.case.bytes > 0 and .ticks > 0' "$work/out" >/dev/null || fail "$name: info: $(head -c 300 "$work/out")"
done

# Fluoroscopy by action script (neuro: a catheter): the pedal down 4 s, 6 mL injected during it,
# the roadmap taken with the pedal up. The figures are printed, in the JSON, and replayed.
cat >"$work/angio.actions" <<'EOF'
0     select catheter
0     insert_to 100 at 100
1000  fluoro on
2500  inject 6 at 3
5000  fluoro off
5100  roadmap
5300  end
EOF
rec="$work/angio.cbxrec"
if expect 0 "$cb" session run --case "$cases/neuro.case" --script "$work/angio.actions" --record "$rec"; then
  for line in "fluoroscopy time *4.00 s" "fluoroscopy runs *1$" "contrast volume *6.00 ml" "dose-area product"; do
    grep -q "$line" "$work/out" || fail "angio: no '$line' in: $(cat "$work/out")"
  done
  grep -q "inject 6.0 mL at 3.0 mL/s from the catheter's tip" "$work/out" || fail "angio: no injection event"
  expect 0 "$cb" session metrics "$rec" --json
  shape session-metrics
  jq -e '(.fluoroscopy_time_s - 4 | fabs) < 1e-6 and (.contrast_volume_ml - 6 | fabs) < 1e-6
         and .fluoroscopy_runs == 1 and .dose_area_product_mGy_cm2 > 0' "$work/out" >/dev/null ||
    fail "angio metrics: $(head -c 600 "$work/out")"
  expect 0 "$cb" session info "$rec" --json
  shape session-info
  jq -e '.controls == {"fluoro_pedal": 2, "inject": 1, "roadmap": 1}' "$work/out" >/dev/null ||
    fail "angio controls: $(jq -c .controls "$work/out")"
  expect 0 "$cb" session replay "$rec" --check
  grep -q "match" "$work/out" || fail "angio replay: $(cat "$work/out")"
fi
# A bad imaging verb or value: one line naming the script's line, exit 2.
printf '0 select catheter\n100 fluoro maybe\n' >"$work/bad_verb.actions"
expect 2 "$cb" session run --case "$cases/neuro.case" --script "$work/bad_verb.actions" --record "$work/bad.cbxrec"
[ "$(wc -l <"$work/out")" -eq 1 ] && grep -q "bad_verb.actions:2: fluoro: expected 'on' or 'off'" "$work/out" ||
  fail "bad verb: $(cat "$work/out")"
printf '0 inject 6 at 50\n' >"$work/bad_rate.actions"
expect 2 "$cb" session run --case "$cases/neuro.case" --script "$work/bad_rate.actions" --record "$work/bad.cbxrec"
[ "$(wc -l <"$work/out")" -eq 1 ] && grep -q "bad_rate.actions:1: inject: rate must be in (0, 30\] mL/s" "$work/out" ||
  fail "bad rate: $(cat "$work/out")"

# Coiling, the command line's part (the bundled procedure: session_cli_coiling_test.sh, long): a
# microcatheter into a 6.4 mm sphere on a 2 mm artery, a 20 mm coil pushed out and detached, the
# next (15 mm, the case's next_coil) loaded at the hub with load_coil, pushed out and detached;
# the record replays them (coil tool, shape, next coil, the detach_coil and load_coil controls)
# and its metrics carry the coiling figures.
coil_case="$cases/../tests/host/session/data/coil_in_sphere.case"  # also test_session's CoilSession
cat >"$work/coil.actions" <<'EOF'
0     select microcatheter
0     insert_to 21 at 20
0     select coil
0     insert_to 20.5 at 20
1200  insert_to 42.5 at 20
2400  detach
2500  insert_to 15 at 40
3000  load_coil
3000  insert_to 20.5 at 40
3600  insert_to 37.5 at 20
4500  detach
4600  insert_to 15 at 40
5000  end
EOF
rec="$work/coil.cbxrec"
expect 0 "$cb" session run --case "$coil_case" --script "$work/coil.actions" --record "$rec"
[ "$(grep -c "coil of the coil detached" "$work/out")" -eq 2 ] || fail "coil: not two detaches: $(tail -5 "$work/out")"
grep -q "^packing density" "$work/out" || fail "coil: no packing density line"
check_run coil '.coil_length_mm > 30 and .packing_density_pct > 0 and .coil_herniated_peak_nodes >= 0 and .coil_herniated_depth_mm >= 0' \
  '.controls.detach_coil == 2 and .controls.load_coil == 1 and .tools[1].kind == "coil"'

# Thrombectomy: the carotid-T aspiration under balloon-guide arrest reperfuses on its first pass
# (eTICI 3), its aspiration and balloon_guide controls are in the record, and it replays:
# check_run's `metrics` replays it with every state hash checked (a `replay --check` too would
# simulate this 17 s record a third time, ~5 s of CPU; that command's own output is checked on the
# angiography and killed records).
rec="$work/ica_t.cbxrec"
expect 0 "$cb" session run --case "$cases/neuro_thrombectomy_ica_t.case" --script "$cases/neuro_thrombectomy_ica_t.actions" --record "$rec"
grep -q "pass 1: eTICI 3" "$work/out" || fail "ica_t: no reperfusion: $(tail -5 "$work/out")"
check_run ica_t '.thrombectomy.passes == 1 and .thrombectomy.etici_final == "3" and .thrombectomy.first_pass_effect and .thrombectomy.emboli == 0' \
  '.controls.aspiration == 2 and .controls.balloon_guide == 2'

# The same record replayed twice gives the same CSV log, byte for byte.
rec="$work/y_bifurcation.cbxrec"
expect 0 "$cb" session replay "$rec" --out "$work/a.csv" --every 10
expect 0 "$cb" session replay "$rec" --out "$work/b.csv" --every 10
cmp -s "$work/a.csv" "$work/b.csv" || fail "two replays of one record differ"
[ "$(wc -l <"$work/a.csv")" -gt 100 ] || fail "replay log too short: $(wc -l <"$work/a.csv") lines"

# Every tool's hand force against the box's limits (`--forces`): the wire alone is the held tool
# throughout, so its peak is the metrics' peak hand force and the held tool's line is its own; the
# coil record has a line per tool and one of the held tool. `session run --forces` prints the same
# lines after its run.
expect 0 "$cb" session replay "$rec" --forces
figures=' peak +[0-9.]+ mN at +[0-9.]+ s; largest change +[0-9.]+ mN/tick at +[0-9.]+ s; [0-9]+ ticks over 100 mN/tick, [0-9]+ over 5000 mN$'
forces_line="^[^ (].*$figures"
held_line="^\\(held tool\\) *$figures"
[ "$(grep -cE "$forces_line" "$work/out")" -eq 1 ] || fail "forces: not one tool line: $(cat "$work/out")"
[ "$(grep -cE "$held_line" "$work/out")" -eq 1 ] || fail "forces: not one held tool line: $(cat "$work/out")"
[ "$(grep -E "$forces_line" "$work/out" | sed -E 's/^[^ ]+ +//')" = "$(grep -E "$held_line" "$work/out" | sed -E 's/^\(held tool\) +//')" ] ||
  fail "forces: the wire alone held, its figures differ from the held tool's: $(cat "$work/out")"
grep -E "$forces_line|$held_line" "$work/out" >"$work/replayed_forces"
expect 0 "$cb" session run --case "$cases/y_bifurcation.case" --script "$work/push.actions" --virtual --record "$work/y2.cbxrec" --forces
grep -E "$forces_line|$held_line" "$work/out" | cmp -s - "$work/replayed_forces" ||
  fail "forces: session run --forces differs from the replay's: $(tail -3 "$work/out")"
peak=$(grep -E "$forces_line" "$work/replayed_forces" | sed -E 's/.* peak +([0-9.]+) mN.*/\1/')
"$cb" session metrics "$rec" --json >"$work/metrics.json" || fail "forces: metrics"
jq -e --argjson p "$peak" '(.peak_hand_force_mN - $p | fabs) < 0.06 and $p > 1' "$work/metrics.json" >/dev/null ||
  fail "forces: peak $peak against the metrics' $(jq .peak_hand_force_mN "$work/metrics.json")"
expect 0 "$cb" session replay "$work/coil.cbxrec" --forces
tools=$("$cb" session info "$work/coil.cbxrec" --json | jq '.tools | length')
[ "$tools" -ge 2 ] && [ "$(grep -cE "$forces_line" "$work/out")" -eq "$tools" ] || fail "forces: $tools tools: $(cat "$work/out")"
[ "$(grep -cE "$held_line" "$work/out")" -eq 1 ] || fail "forces: not one held tool line: $(cat "$work/out")"

# Every tool's state tick by tick over a window (`--trace FROM-TO`): a line per tool and tick, the
# held one marked, before the replay's summary; a window that is not FROM-TO is a usage error.
expect 0 "$cb" session replay "$work/coil.cbxrec" --trace 1.000-1.002
trace_line='^ +[0-9]+\.[0-9]{3} .* ins +-?[0-9.]+ F +-?[0-9.]+ dF +[-+][0-9.]+ own .* converged [01] its [0-9]+ parts [0-9]+ \| tip .* \| wall.* \| rods'
[ "$(grep -cE "$trace_line" "$work/out")" -eq $((3 * tools)) ] || fail "trace: not 3 x $tools lines: $(head -c 600 "$work/out")"
[ "$(grep -c ' held ins ' "$work/out")" -eq 3 ] || fail "trace: not one held tool a tick: $(head -c 600 "$work/out")"
grep -q "replayed .* state hashes checked" "$work/out" || fail "trace: no summary line"
expect 2 "$cb" session replay "$work/coil.cbxrec" --trace 2-1
grep -q -- "--trace must be FROM-TO" "$work/out" || fail "trace: no usage line for 2-1: $(head -3 "$work/out")"
expect 2 "$cb" session replay "$work/coil.cbxrec" --trace 1.5
expect 2 "$cb" session replay "$work/coil.cbxrec" --trace x-2

# Bad records: one line naming the file and the byte, exit 2; nothing written.
head -c 100 "$rec" >"$work/cut.cbxrec"
expect 2 "$cb" session replay "$work/cut.cbxrec" --check
[ "$(wc -l <"$work/out")" -eq 1 ] && grep -q "cut.cbxrec: byte" "$work/out" || fail "truncated header: $(cat "$work/out")"
printf 'not a record at all' >"$work/foreign.cbxrec"
expect 2 "$cb" session info "$work/foreign.cbxrec"
[ "$(wc -l <"$work/out")" -eq 1 ] || fail "foreign file: $(cat "$work/out")"
expect 2 "$cb" session metrics "$work/missing.cbxrec"
# A flipped byte in the last block: its CRC catches it.
size=$(stat -c %s "$rec")
cp "$rec" "$work/flip.cbxrec"
printf '\xff' | dd of="$work/flip.cbxrec" bs=1 seek=$((size - 20)) conv=notrunc status=none
expect 2 "$cb" session replay "$work/flip.cbxrec" --check
grep -q "byte" "$work/out" || fail "flipped byte: $(cat "$work/out")"

# Against the emulated box in real time: its hand pushes at 20 mm/s for 1.5 s and twists.
exec 3< <(exec "$bin/cathbox-emu" --socket "$work/emu.sock" --duration 120 \
  --hand-insertion v:20mm/s:1500ms,free:60s --hand-rotation v:2rad/s:1s,free:60s 2>&1)
emu_pid=$!
read -r line <&3
case "$line" in *listening*) ;; *) fail "emulator did not start: $line" ;; esac
if [ -n "$quick" ]; then
  emu_cases="$cases/y_bifurcation.case"
else
  emu_cases=$(ls "$cases"/*.case)
fi
for c in $emu_cases; do
  name=$(basename "$c" .case)
  rec="$work/emu_$name.cbxrec"
  expect 0 "$cb" session run --case "$c" --emu "$work/emu.sock" --seconds 2 --record "$rec" || continue
  expect 0 "$cb" session replay "$rec" --check
  expect 0 "$cb" session info "$rec" --json
  shape session-info
  jq -e '.device.board == "cathbox-emu"' "$work/out" >/dev/null || fail "$name: no box in the header: $(head -c 300 "$work/out")"
done

# SIGKILL mid-run: the record reads and replays up to its last complete block.
rec="$work/killed.cbxrec"
exec 4< <(exec "$cb" session run --case "$cases/y_bifurcation.case" --emu "$work/emu.sock" --seconds 60 \
  --record "$rec" --progress 2>&1)
run_pid=$!
blocks=0
while read -r line <&4; do
  case "$line" in recorded*) blocks=$((blocks + 1)) ;; esac
  [ "$blocks" -ge 2 ] && break
done
kill -KILL "$run_pid" 2>/dev/null
wait "$run_pid" 2>/dev/null
run_pid=""
[ "$blocks" -ge 2 ] || fail "the run wrote no blocks before it was killed"
expect 0 "$cb" session replay "$rec" --check
grep -q "match" "$work/out" || fail "killed record: $(cat "$work/out")"
expect 0 "$cb" session info "$rec" --json
shape session-info
jq -e '.ticks > 0' "$work/out" >/dev/null || fail "killed record: no ticks: $(head -c 300 "$work/out")"

finish

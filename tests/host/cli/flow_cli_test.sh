#!/usr/bin/env bash
# Checks `cathbox flow info` against the built tool: every bundled case, the JSON (parsed by
# jq), flows that balance, and one-line file:line errors with exit code 2.
# Usage: flow_cli_test.sh CATHBOX SOURCE_DIR WORK_DIR
source "$(dirname "${BASH_SOURCE[0]}")/cli_check.sh"

for f in "$src"/cases/*.hclm "$src"/cases/*.case; do
  expect 0 "$cathbox" flow info "$f"
  grep -q "^inflow" "$work/out" || fail "info $f: $(head -5 "$work/out")"
  expect 0 "$cathbox" flow info "$f" --json
  jq -e '.segments | length > 0' "$work/out" >/dev/null || fail "json $f"
  json_shape flow-info
  # Inflow equals the outlets' total.
  jq -e '([.terminals[] | select(.role == "outlet") | .flow_ml_min] | add) as $out
         | (.total_inflow_ml_min - $out) | fabs < 1e-6 * (1 + $out)' "$work/out" >/dev/null || fail "balance $f"
done

expect 0 "$cathbox" flow info "$src/cases/neuro.case" --json
jq -e '.segments[] | select(.name == "right_internal_carotid") | .flow_ml_min > 240 and .flow_ml_min < 320' \
  "$work/out" >/dev/null || fail "right ICA flow: $(jq '.segments[12]' "$work/out")"
jq -e '.segments[] | select(.name == "left_vertebral") | .mean_velocity_mm_s > 50' "$work/out" >/dev/null || fail "VA velocity"
jq -e '[.terminals[] | select(.role == "inlet")] | length == 1' "$work/out" >/dev/null || fail "one inlet"

# A case with overrides, and bad ones: exit 2, one line naming file:line.
printf 'vessel %s/cases/neuro.hclm\nflow outlet 16 150\nflow closed 17\n' "$src" >"$work/over.case"
expect 0 "$cathbox" flow info "$work/over.case" --json
jq -e '.terminals[] | select(.segment_id == 16) | .flow_ml_min > 149.99 and .overridden' "$work/out" >/dev/null || fail "override"
jq -e '.terminals[] | select(.segment_id == 17) | .role == "closed"' "$work/out" >/dev/null || fail "closed"
printf 'vessel %s/cases/neuro.hclm\n\nflow outlet 99 150\n' "$src" >"$work/bad_id.case"
printf 'vessel %s/cases/neuro.hclm\nflow viscosity -1\n' "$src" >"$work/bad_value.case"
for bad in bad_id:3 bad_value:2; do
  file="$work/${bad%%:*}.case"
  expect 2 "$cathbox" flow info "$file"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "$bad: want one stderr line, got: $(cat "$work/err")"
  grep -q "^$file:${bad##*:}: " "$work/err" || fail "$bad: no file:line in: $(cat "$work/err")"
done
printf 's 1\ng 1\np 0\nc 0\nn 2\nv 0 0 0 1\nw 0 0 1 1\n' >"$work/bad.hclm"
expect 2 "$cathbox" flow info "$work/bad.hclm"
grep -q "^$work/bad.hclm:7: " "$work/err" || fail "bad hclm: $(cat "$work/err")"
expect 2 "$cathbox" flow info "$work/missing.case"
expect 2 "$cathbox" flow info
expect 2 "$cathbox" flow frobnicate
expect 0 "$cathbox" flow help

finish "flow cli"

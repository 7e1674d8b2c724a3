#!/usr/bin/env bash
# One thrombectomy technique script on its case through `cathbox session` (labelled long: 60-
# 260 s of virtual time, 30-180 s of CPU each; docs/session/thrombectomy.md, "The technique
# scripts"): the run headless in virtual time, `session replay --check` of its record (every
# state hash), and its metrics against the jq filter WANT (the script's stated eTICI, passes,
# emboli).
# Usage: thrombectomy_script_test.sh BIN_DIR CASES_DIR CASE SCRIPT WANT
source "$(dirname "${BASH_SOURCE[0]}")/session_cli_lib.sh"
case_file="$cases/$3"
script="$cases/$4"
want="$5"

rec="$work/run.cbxrec"
expect 0 "$cb" session run --case "$case_file" --script "$script" --virtual --record "$rec"
expect 0 "$cb" session replay "$rec" --check
check_run "$4" "$want" '.ticks > 0'
# The figures, for the log (docs/session/thrombectomy.md quotes them).
"$cb" session metrics "$rec" --json | jq -c --arg s "$4" '{script: $s, peak_hand_force_mN, unconverged_pct}
  + (.thrombectomy | {etici_final, passes, emboli, retrieval_force_peak_N, time_to_reperfusion_s})' || fail "$4: no figures"
finish

#!/usr/bin/env bash
# The bundled coiling procedure through `cathbox session` (labelled long: ~25 s, the run and the
# hash-checked replay `session metrics` makes of it): cases/neuro_coiling.actions deploys and
# detaches its two coils (the second loaded with load_coil) at the aneurysm of
# cases/neuro_coiling.case; the record replays them (coil tool, shape, next coil and the
# detach_coil and load_coil controls) and its metrics carry the coiling figures. The command
# line's own coil checks run by default in session_cli_test.sh, on a small analytic case.
# Usage: session_cli_coiling_test.sh BIN_DIR CASES_DIR
source "$(dirname "${BASH_SOURCE[0]}")/session_cli_lib.sh"

rec="$work/coiling.cbxrec"
expect 0 "$cb" session run --case "$cases/neuro_coiling.case" --script "$cases/neuro_coiling.actions" --record "$rec"
grep -q "coil of the coil detached" "$work/out" || fail "coiling: no detach: $(tail -5 "$work/out")"
grep -q "^packing density" "$work/out" || fail "coiling: no packing density line"
check_run coiling '.coil_length_mm >= 99 and .packing_density_pct > 2 and .packing_density_pct < 3 and .target_reached' \
  '.controls.detach_coil == 2 and .controls.load_coil == 1 and .tools[3].kind == "coil"'
finish

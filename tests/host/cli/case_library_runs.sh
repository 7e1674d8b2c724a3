#!/usr/bin/env bash
# The library cases whose scripted run reaches the target (cases/README.md), headless in virtual
# time: `cathbox session run --virtual` then `cathbox session metrics --json` must say
# target_reached. Usage: case_library_runs.sh CATHBOX SOURCE_DIR OUT_DIR
set -euo pipefail
cathbox=$1 src=$2 out=$3
mkdir -p "$out"
cd "$src/cases/library"
fail=0
for name in arch_type1 arch_type2 arch_type3 arch_bovine ica_straight ica_tortuous ica_coil ica_kink aneurysm_mca aneurysm_pcom aneurysm_acom aneurysm_basilar; do
  "$cathbox" session run --case "$name.case" --script "$name.actions" --virtual --record "$out/$name.cbxrec" >/dev/null
  if "$cathbox" session metrics "$out/$name.cbxrec" --json | grep -q '"target_reached": *true'; then
    echo "$name: target reached"
  else
    echo "$name: target NOT reached" >&2
    fail=1
  fi
done
exit $fail

#!/usr/bin/env bash
# The case built from a public surface (cases/sofa_aneurysm/, cases/README.md): its bundled PLY
# imports as the bundled graph, and the case's scripted run reaches the target both on that fresh
# import and on the bundled case folder, headless in virtual time (`cathbox session metrics --json`
# says target_reached). Usage: public_surface_case_test.sh CATHBOX SOURCE_DIR OUT_DIR
set -euo pipefail
cathbox=$1 bundle=$2/cases/sofa_aneurysm out=$3
rm -rf "$out"
mkdir -p "$out"
fail() { echo "public_surface_case_test: $*" >&2; exit 1; }

"$cathbox" vessel import "$bundle/aneurysm3D_1.ply" -o "$out/imported" >/dev/null
graph() { "$cathbox" vessel info "$1" --json | grep -o '"\(segments\|junctions\|free_ends\)": *[0-9]*' | tr '\n' ' '; }
[ "$(graph "$out/imported/vessel.hclm")" = "$(graph "$bundle/vessel.hclm")" ] ||
  fail "the import gives $(graph "$out/imported/vessel.hclm"), the bundled vessel.hclm $(graph "$bundle/vessel.hclm")"
cp "$bundle/sofa_aneurysm.case" "$bundle/sofa_aneurysm.actions" "$out/imported/"

for dir in "$out/imported" "$bundle"; do
  "$cathbox" session run --case "$dir/sofa_aneurysm.case" --script "$dir/sofa_aneurysm.actions" --virtual \
    --record "$out/run.cbxrec" >/dev/null
  "$cathbox" session metrics "$out/run.cbxrec" --json >"$out/metrics.json"
  grep -q '"target_reached": *true' "$out/metrics.json" || fail "$dir: the scripted run does not reach the target"
  echo "$dir: target reached"
done

#!/usr/bin/env bash
# The case built from a public surface (cases/sofa_aneurysm/, cases/README.md): its bundled PLY
# imports as the bundled graph (inlet at the entry's end, the sac closed), and the case's scripted run reaches the target both on that fresh
# import and on the bundled case folder, headless in virtual time (`cathbox session metrics --json`
# says target_reached). Usage: public_surface_case_test.sh CATHBOX SOURCE_DIR OUT_DIR
set -euo pipefail
cathbox=$1 bundle=$2/cases/sofa_aneurysm out=$3
rm -rf "$out"
mkdir -p "$out"
fail() { echo "public_surface_case_test: $*" >&2; exit 1; }

# The command cases/README.md gives: the inlet at the case's entry, the sac named.
"$cathbox" vessel import "$bundle/aneurysm3D_1.ply" -o "$out/imported" --inlet=-19.67,-11.52,-13.17 --sac 6.8,0.1,1.8 >/dev/null
graph() { "$cathbox" vessel info "$1" --json | grep -o '"\(segments\|junctions\|free_ends\)": *[0-9]*' | tr '\n' ' '; }
[ "$(graph "$out/imported/vessel.hclm")" = "$(graph "$bundle/vessel.hclm")" ] ||
  fail "the import gives $(graph "$out/imported/vessel.hclm"), the bundled vessel.hclm $(graph "$bundle/vessel.hclm")"
cp "$bundle/sofa_aneurysm.case" "$bundle/sofa_aneurysm.actions" "$out/imported/"
# The flow enters at the entry's end (segment 1's start) and the sac (segment 3) is closed.
for dir in "$out/imported" "$bundle"; do
  "$cathbox" flow info "$dir/sofa_aneurysm.case" >"$out/flow.txt"
  grep -Eq '^ +1 +proximal +inlet ' "$out/flow.txt" || fail "$dir: segment 1's start is not the inlet: $(cat "$out/flow.txt")"
  grep -Eq '^ +3 +aneurysm ' "$out/flow.txt" && grep -Eq '^ +3 +distal +closed ' "$out/flow.txt" ||
    fail "$dir: segment 3 is not a closed sac named aneurysm: $(cat "$out/flow.txt")"
done

for dir in "$out/imported" "$bundle"; do
  "$cathbox" session run --case "$dir/sofa_aneurysm.case" --script "$dir/sofa_aneurysm.actions" --virtual \
    --record "$out/run.cbxrec" >/dev/null
  "$cathbox" session metrics "$out/run.cbxrec" --json >"$out/metrics.json"
  grep -q '"target_reached": *true' "$out/metrics.json" || fail "$dir: the scripted run does not reach the target"
  echo "$dir: target reached"
done

#!/usr/bin/env bash
# Checks `cathbox vessel import` against the built tool: every example format imports (summary
# line, exit 0) and the result meshes and runs in the simulator; bad input gives exactly one
# stderr line naming file and line (or byte) and exit 2; bad options exit 2.
# With the trainer given, it runs the imported carotid bifurcation headless with the scripted hand.
# Usage: vessel_import_cli_test.sh CATHBOX SOURCE_DIR WORK_DIR [TRAINER]
source "$(dirname "${BASH_SOURCE[0]}")/cli_check.sh"
examples="$src/sim/vessel_import/examples"

# Every format: a summary line, an HCLM that validates, meshes closed and manifold.
for f in carotid_bifurcation_centerlines.vtp vertebrobasilar_tracts.vtk mca_bifurcation.mrk.json cortical_tree.swc; do
  expect 0 "$cathbox" vessel import "$examples/$f" -o "$work/$f.hclm"
  grep -q "segments, .* junctions, .* cycles, .*radius .* mm; .*radius filter" "$work/out" || fail "summary of $f: $(cat "$work/out")"
  [ -s "$work/err" ] && fail "stderr on success for $f: $(cat "$work/err")"
  expect 0 "$cathbox" vessel validate "$work/$f.hclm"
  expect 0 "$cathbox" vessel mesh "$work/$f.hclm" -o "$work/$f.ply"
  grep -q "closed, manifold" "$work/out" || fail "mesh of imported $f: $(cat "$work/out")"
done
grep -q "overlapping polylines split off a shared trunk" <("$cathbox" vessel import "$examples/carotid_bifurcation_centerlines.vtp" -o "$work/c.hclm") ||
  fail "VMTK overlap not reported"
expect 0 "$cathbox" vessel import "$examples/vertebrobasilar_tracts.vtk" -o "$work/vb.hclm"
grep -q "8 tracts (CenterlineIds, TractIds) rejoined into 3 centrelines" "$work/out" || fail "tracts: $(cat "$work/out")"
expect 0 "$cathbox" vessel info "$work/vb.hclm" --json
# Two vertebrals, basilar, two posterior cerebrals: two junctions (oriented from the widest free
# end, the left vertebral: the file says nothing about the flow).
json_shape vessel-info
jq -e '.segments == 5 and .junctions == 2' "$work/out" >/dev/null || fail "vertebrobasilar network: $(cat "$work/out")"

# Options: the format named, units (cm: ten times the lengths), a radius array, the filter off.
cp "$examples/cortical_tree.swc" "$work/tree.txt"
expect 0 "$cathbox" vessel import "$work/tree.txt" --format swc --units cm -o "$work/tree_cm.hclm"
grep -q "radius 4.2.*\.\.12.4 mm" "$work/out" || fail "--units cm: $(cat "$work/out")"
expect 0 "$cathbox" vessel import "$examples/carotid_bifurcation_centerlines.vtp" --radius-array MaximumInscribedSphereRadius --no-radius-filter -o "$work/raw.hclm"
grep -q "radius filter off" "$work/out" || fail "--no-radius-filter: $(cat "$work/out")"

# Two branches 10 degrees apart and 6 radii long: imported and meshed, the junction by the
# spherical-hull fallback (named in both summaries); refused with --no-junction-fallback.
awk 'BEGIN {
  print "1 0 0 0 0 1 -1"; id = 1
  for (i = 1; i <= 20; ++i) { id++; print id, 0, 0, 0, i * 0.5, 1, id - 1 }
  for (s = -1; s <= 1; s += 2) {
    prev = 21
    for (i = 1; i <= 6; ++i) { id++; printf "%d 0 %.4f 0 %.4f 0.5 %d\n", id, s * i * 0.5 * sin(0.0873), 10 + i * 0.5 * cos(0.0873), prev; prev = id }
  }
}' >"$work/narrow.swc"
expect 0 "$cathbox" vessel import "$work/narrow.swc" -o "$work/narrow.hclm"
grep -q "1 junction meshed by the spherical-hull fallback: junction 0 (segments" "$work/out" || fail "narrow junction note: $(cat "$work/out")"
expect 0 "$cathbox" vessel mesh "$work/narrow.hclm" -o "$work/narrow.ply"
grep -q "closed, manifold" "$work/out" || fail "narrow junction mesh: $(cat "$work/out")"
grep -q "meshed by the spherical-hull fallback: junction 0" "$work/out" || fail "narrow junction mesh note: $(cat "$work/out")"
expect 2 "$cathbox" vessel mesh "$work/narrow.hclm" -o "$work/narrow.ply" --no-junction-fallback
grep -q "junction 0 (segments .*): branches overlap" "$work/err" || fail "--no-junction-fallback: $(cat "$work/err")"

# Bad input: exit 2, one stderr line starting file:line (or file:) and nothing written.
printf '1 0 0 0 0 1 -1\n2 0 0 0 1 1 1\n3 0 0 zero 2 1 2\n' >"$work/bad.swc"
printf '{\n "markups": [\n  {"type": "Curve",, }\n ]\n}\n' >"$work/bad.mrk.json"
printf '# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0\n0 0 1\nLINES 1 3\n2 0 1\nPOINT_DATA 2\nSCALARS Thickness double 1\nLOOKUP_TABLE default\n1 1\n' >"$work/noradius.vtk"
printf 'this is not a vtk file\n' >"$work/garbage.vtk"
for bad in bad.swc:3 bad.mrk.json:3 noradius.vtk: garbage.vtk: missing.swc:; do
  file="$work/${bad%%:*}"
  line="${bad##*:}"
  rm -f "$work/out.hclm"
  expect 2 "$cathbox" vessel import "$file" -o "$work/out.hclm"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "$bad: want one stderr line, got: $(cat "$work/err")"
  grep -q "^$file:$line" "$work/err" || fail "$bad: no $file:$line in: $(cat "$work/err")"
  [ -e "$work/out.hclm" ] && fail "$bad: an output was written"
done
grep -q "no radius array" <("$cathbox" vessel import "$work/noradius.vtk" -o "$work/x.hclm" 2>&1) || fail "no radius array message"
expect 2 "$cathbox" vessel import "$examples/cortical_tree.swc"                       # no -o
expect 2 "$cathbox" vessel import "$examples/cortical_tree.swc" -o "$work/x.hclm" --units furlong
expect 2 "$cathbox" vessel import "$examples/cortical_tree.swc" -o "$work/x.hclm" --format stl
expect 2 "$cathbox" vessel import "$work/tree.txt" -o "$work/x.hclm"                   # format unknown by name

# The imported vertebrobasilar tree runs in the simulator: a wire pushed in from the root.
printf "0 insert_to 40 at 20\n2500 end\n" >"$work/push.actions"
expect 0 "$cathbox" sim run --case "$work/vb.hclm" --script "$work/push.actions" --out "$work/run.csv" --every 100
[ "$(wc -l <"$work/run.csv")" -gt 10 ] || fail "sim run log: $(head -3 "$work/run.csv")"

# A surface as the case's wall: the Y bifurcation meshed, written as STL and imported into a case
# folder; a session runs on the imported lumen (target: the left branch's end, segment 2 of the
# extracted graph) and its record, which carries the lumen, replays without the file.
expect 0 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/y.stl"
rm -rf "$work/ycase"
expect 0 "$cathbox" vessel import "$work/y.stl" -o "$work/ycase"
grep -q "^surface lumen.cbxmesh" "$work/ycase/y.case" || fail "case folder: $(cat "$work/ycase/y.case")"
# --surface-out is written with a case folder too (it was ignored), the same lumen as the case's.
rm -rf "$work/y_lumen.cbxmesh" "$work/ycase2" "$work/swccase"
expect 0 "$cathbox" vessel import "$work/y.stl" -o "$work/ycase2" --surface-out "$work/y_lumen.cbxmesh"
cmp -s "$work/y_lumen.cbxmesh" "$work/ycase2/lumen.cbxmesh" || fail "--surface-out with a case folder: not the case's lumen"
grep -q "^$work/ycase2/y.case: .*segments" "$work/out" || fail "case folder summary: $(cat "$work/out")"
expect 2 "$cathbox" vessel import "$examples/cortical_tree.swc" -o "$work/swccase" --surface-out "$work/x.ply"
[ -e "$work/swccase" ] && fail "--surface-out of a centreline file: a case folder was written"
printf "0 insert_to 60 at 30\n2500 end\n" >"$work/y.actions"
expect 0 "$cathbox" session run --case "$work/ycase/y.case" --script "$work/y.actions" --virtual --record "$work/y.cbxrec"
expect 0 "$cathbox" session info "$work/y.cbxrec"
grep -q "^surface  *.*/lumen.cbxmesh ([0-9]* bytes)" "$work/out" || fail "record info: $(cat "$work/out")"
rm "$work/ycase/lumen.cbxmesh"
expect 0 "$cathbox" session replay "$work/y.cbxrec" --check
grep -q "every state hash matches" "$work/out" || fail "replay of the surface case: $(cat "$work/out")"
printf "cathbox-case 1\nvessel vessel.hclm\nsurface missing.cbxmesh\n" >"$work/ycase/bad.case"
expect 2 "$cathbox" sim run --case "$work/ycase/bad.case" --script "$work/y.actions" --out "$work/x.csv"
grep -q "missing.cbxmesh: cannot open the case's surface" "$work/err" || fail "missing surface: $(cat "$work/err")"

# The trainer: the scripted hand drives the wire through the imported carotid (virtual time).
if [ -n "${4:-}" ]; then
  expect 0 "$cathbox" vessel import "$examples/carotid_bifurcation_centerlines.vtp" -o "$work/carotid.hclm"
  expect 0 "$4" --case "$work/carotid.hclm" --no-box --headless
  grep -q "end of run" "$work/out" || fail "trainer on the imported carotid: $(tail -5 "$work/out")"
  length=$(sed -n 's/^tip path length *\([0-9.]*\) mm/\1/p' "$work/out")
  awk -v l="${length:-0}" 'BEGIN { exit !(l > 80) }' || fail "the wire went only ${length:-?} mm into the imported carotid"
fi

finish "vessel import cli"

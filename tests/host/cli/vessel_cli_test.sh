#!/usr/bin/env bash
# Checks the `cathbox vessel` commands against the built tool: exit codes, one-line file:line
# errors on bad input, and the files they write. Usage: vessel_cli_test.sh CATHBOX SOURCE_DIR WORK_DIR
source "$(dirname "${BASH_SOURCE[0]}")/cli_check.sh"

for c in neuro neuro_aneurysm neuro_stenosis y_bifurcation seed_catheter; do
  expect 0 "$cathbox" vessel validate "$src/cases/$c.hclm"
  grep -q ": ok (" "$work/out" || fail "validate $c printed $(cat "$work/out")"
done

expect 0 "$cathbox" vessel info "$src/cases/neuro.hclm"
grep -q "^cycles *4$" "$work/out" || fail "info neuro: $(cat "$work/out")"
expect 0 "$cathbox" vessel info "$src/cases/neuro.hclm" --json
json_shape vessel-info
jq -e '.cycles == 4' "$work/out" >/dev/null || fail "info --json: $(cat "$work/out")"
jq -e '.junction_kinds.confluence == 4' "$work/out" >/dev/null || fail "info --json kinds: $(cat "$work/out")"

# Bad files: exit 2, exactly one stderr line naming file:line.
printf 's 1\ng 1\np 0\nc 0\nn 3\nv 0 0 0 1\nv 0 0 1 0\nv 0 0 2 1\n' >"$work/bad_radius.hclm"
printf 's 1\ng 1\np 0\nc 0\nn 2\nv 0 0 0 1\nw 0 0 1 1\n' >"$work/bad_label.hclm"
for bad in bad_radius:7 bad_label:7; do
  file="$work/${bad%%:*}.hclm"
  line="${bad##*:}"
  for cmd in validate info "mesh -o $work/x.obj"; do
    # shellcheck disable=SC2086
    expect 2 "$cathbox" vessel $cmd "$file"
    [ "$(wc -l <"$work/err")" -eq 1 ] || fail "$cmd $bad: want one stderr line, got: $(cat "$work/err")"
    grep -q "^$file:$line: " "$work/err" || fail "$cmd $bad: no file:line in: $(cat "$work/err")"
  done
done
expect 2 "$cathbox" vessel validate "$work/missing.hclm"
expect 2 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm"                  # no -o
expect 2 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/x.xyz" # unknown format
expect 2 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/x.obj" --ring 2
expect 2 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/x.obj" --level nine
expect 2 "$cathbox" vessel frobnicate
grep -q "^usage: cathbox vessel validate FILE$" "$work/err" || fail "usage after an error: $(cat "$work/err")"
# help, --help and the usage after an error come from one description (host/cli/include/cli/usage.hpp)
expect 0 "$cathbox" vessel help
cp "$work/out" "$work/help.txt"
grep -q "^       cathbox vessel mesh FILE -o OUT.obj|.ply|.stl|.cbxmesh \[--ring M\]" "$work/help.txt" || fail "help synopsis: $(cat "$work/help.txt")"
grep -q -- "--radius-array NAME *the point array holding the radius" "$work/help.txt" || fail "help options: $(cat "$work/help.txt")"
expect 0 "$cathbox" vessel --help
cmp -s "$work/out" "$work/help.txt" || fail "vessel --help differs from vessel help"
expect 2 "$cathbox" vessel generate no_such_case -o "$work/x.hclm"

# Import: --inlet and --sac take X,Y,Z; a bad value or a sac point on a branching segment is
# refused in one line naming the option, exit 2 (sim/vessel_import/README.md, "Inlet and sac").
ply="$src/cases/sofa_aneurysm/aneurysm3D_1.ply"
expect 2 "$cathbox" vessel import "$ply" -o "$work/imp" --inlet 1,2
grep -q "^cathbox vessel: option --inlet: '1,2' is not 3 comma-separated finite numbers$" "$work/err" || fail "--inlet 1,2: $(cat "$work/err")"
expect 2 "$cathbox" vessel import "$ply" -o "$work/imp" --sac 1,2,nan
grep -q "^cathbox vessel: option --sac: " "$work/err" || fail "--sac 1,2,nan: $(cat "$work/err")"
# --sac without --inlet: the sac's end (the widest) would be the inlet and a point at the case's
# entry would name the entry's segment the sac; refused before reading IN.
expect 2 "$cathbox" vessel import "$ply" -o "$work/imp" --sac=-19.67,-11.52,-13.17
grep -q "^cathbox vessel: --sac: needs --inlet (" "$work/err" || fail "--sac without --inlet: $(cat "$work/err")"
[ ! -e "$work/imp" ] || fail "--sac without --inlet wrote $work/imp"
expect 2 "$cathbox" vessel import "$ply" -o "$work/imp" --inlet=-19.67,-11.52,-13.17 --sac 0,0,0
[ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "^$ply: --sac: the segment nearest the point (1, .*) is not blind" "$work/err" ||
  fail "--sac on the parent: $(cat "$work/err")"

# Meshing: every format, control mesh, open ends.
for ext in obj ply stl; do
  expect 0 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/y.$ext" --ring 8 --level 2
  [ -s "$work/y.$ext" ] || fail "mesh .$ext wrote nothing"
  grep -q "closed, manifold" "$work/out" || fail "mesh .$ext: $(cat "$work/out")"
done
head -c 3 "$work/y.ply" | grep -q ply || fail "ply header"
grep -q "^g junction_0" "$work/y.obj" || fail "obj groups per region"
# The thesis' counts (4 sum k_i points, 4 sum (k_i - 1) + 7 faces) with a ring per HCLM point.
expect 0 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/c.obj" --ring 4 --control-mesh --no-caps --rings per-point
grep -q "control mesh 300 vertices 295 faces" "$work/out" || fail "control mesh counts: $(cat "$work/out")"
expect 0 "$cathbox" vessel mesh "$src/cases/neuro_stenosis.hclm" -o "$work/s.ply" --smoothing moving-average --no-junction-fit
grep -q "closed, manifold" "$work/out" || fail "mesh with the thesis smoothing: $(cat "$work/out")"
expect 2 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/x.obj" --smoothing gaussian
expect 2 "$cathbox" vessel mesh "$src/cases/y_bifurcation.hclm" -o "$work/x.obj" --rings every-mm

# scripts/sac-neck: the opening of a sac as meshed. The ACom sac has no branch at its base, so its
# neck plane reads its nominal 2.2 mm neck (2.02-2.85 mm). The small MCA sac (a round 4.0 mm dome
# on a 1.8 mm neck: small ruptured aneurysms measured dome 3.9 +- 1.1 mm, neck 1.6 mm, aspect
# ratio 2.1 +- 0.6, Dolati et al., PMC4494560, 2015) starts at the M1's end: its first 2 mm are
# the bifurcation with both M2 origins (wide), its neck 2.2 mm out is round and 1.6-2.0 mm across,
# its dome 3.8-4.1 mm, and no wall 4.3 mm past the neck (depth / neck under 2.4). A file without a
# sac, or a missing argument: exit 2.
expect 0 "$cathbox" vessel mesh "$src/cases/library/aneurysm_acom.hclm" -o "$work/acom.obj"
python3 "$src/scripts/sac-neck" "$src/cases/library/aneurysm_acom.hclm" "$work/acom.obj" 0 >"$work/neck" ||
  fail "sac-neck on the ACom sac"
awk '/^depth/ { if ($5 < 1.8 || $7 > 3.2) bad = 1; seen = 1 } END { exit !(seen && !bad) }' "$work/neck" ||
  fail "sac-neck: the ACom neck is not near its 2.2 mm: $(cat "$work/neck")"
expect 0 "$cathbox" vessel mesh "$src/cases/neuro_small_aneurysm.hclm" -o "$work/small.obj"
python3 "$src/scripts/sac-neck" "$src/cases/neuro_small_aneurysm.hclm" "$work/small.obj" 0 2.2 4.2 6.5 >"$work/neck" ||
  fail "sac-neck on the small sac"
awk '/^depth +0.00/ { if ($7 > 6.0) ok++ }
     /^depth +2.20/ { if ($5 >= 1.6 && $7 <= 2.0) ok++ }
     /^depth +4.20/ { if ($5 >= 3.8 && $7 <= 4.1) ok++ }
     /^depth +6.50/ && /no wall/ { ok++ }
     END { exit ok != 4 }' "$work/neck" ||
  fail "sac-neck: the small sac's bifurcation, neck, dome or depth: $(cat "$work/neck")"
python3 "$src/scripts/sac-neck" "$src/cases/y_bifurcation.hclm" "$work/acom.obj" >"$work/neck" 2>&1 &&
  fail "sac-neck: a vessel without a sac was accepted"
grep -q "no segment named" "$work/neck" || fail "sac-neck: no sac: $(cat "$work/neck")"
python3 "$src/scripts/sac-neck" "$src/cases/y_bifurcation.hclm" >/dev/null 2>&1 && fail "sac-neck: one argument accepted"

# Generate: bundled cases reproduce the shipped files; random models validate.
expect 0 "$cathbox" vessel generate --all "$work/cases"
for c in neuro neuro_aneurysm neuro_small_aneurysm neuro_stenosis y_bifurcation; do
  cmp -s "$work/cases/$c.hclm" "$src/cases/$c.hclm" || fail "cases/$c.hclm differs from the generator"
done
expect 0 "$cathbox" vessel generate random-tree --seed 3 --segments 30 -o "$work/tree.hclm"
expect 0 "$cathbox" vessel validate "$work/tree.hclm"
expect 0 "$cathbox" vessel generate random-graph --seed 2 --cycles 2 -o "$work/graph.hclm"
expect 0 "$cathbox" vessel info "$work/graph.hclm"
grep -q "^cycles *2$" "$work/out" || fail "random graph cycles: $(cat "$work/out")"

finish "vessel cli"

#!/usr/bin/env bash
# scripts/robustness on the Y bifurcation (its smoke run; the runs it measures are opt-in): the
# bundled script's row is `session run --forces`'s held tool, the scaled scripts' speeds are the
# bundled ones times the scale, and a bad argument is one line and exit 2.
# Usage: robustness_test.sh BIN_DIR CASES_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/session_cli_lib.sh"
src="$3"
export CATHBOX="$cb"

expect 0 "$src/scripts/robustness" --runs y_bifurcation_left --speeds 0.99,1.01 --jobs 2 --keep "$work/keep"
row='^y_bifurcation_left +(bundled|x0\.99|x1\.01) +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +ok$'
[ "$(grep -cE "$row" "$work/out")" -eq 3 ] || fail "not three rows: $(cat "$work/out")"
cp "$work/out" "$work/table"

# The bundled row's held tool: the figures of the same run's own --forces line.
expect 0 "$cb" session run --case "$cases/y_bifurcation.case" --script "$cases/y_bifurcation_left.actions" --virtual \
  --record "$work/y.cbxrec" --forces
held=$(sed -nE 's/^\(held tool\) .* largest change +([0-9.]+) mN\/tick at +([0-9.]+) s.*/\1 \2/p' "$work/out")
[ -n "$held" ] || fail "no held tool line: $(tail -3 "$work/out")"
bundled=$(awk '$1 == "y_bifurcation_left" && $2 == "bundled" { print $3, $4 }' "$work/table")
[ "$held" = "$bundled" ] || fail "bundled row '$bundled' against the run's held tool '$held'"

# Speeds scaled, nothing else: `insert_to 40 at 30` at x1.01 is `at 30.3`, the times kept.
awk 'NR == FNR { if ($0 !~ /^#/) a[++n] = $0; next }
     $0 !~ /^#/ { m++; split(a[m], f); if ($1 != f[1] || $2 != f[2]) bad = 1
                  if ($(NF - 1) == "at") { d = $NF - f[NF] * 1.01; if (d * d > 1e-12) bad = 1 } }
     END { exit bad || m != n }' "$cases/y_bifurcation_left.actions" "$work/keep/y_bifurcation_left.1.01.actions" ||
  fail "the x1.01 script is not the bundled one with its speeds x1.01: $(cat "$work/keep/y_bifurcation_left.1.01.actions")"

# Bad arguments: one line naming the argument, exit 2, nothing run.
for args in "--speeds 3" "--speeds fast" "--runs nosuch" "--jobs 0" "--frobnicate"; do
  # shellcheck disable=SC2086
  expect 2 "$src/scripts/robustness" $args
  grep -q "^scripts/robustness: " "$work/out" || fail "$args: no one-line reason: $(cat "$work/out")"
done
finish

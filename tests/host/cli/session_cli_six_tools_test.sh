#!/usr/bin/env bash
# Six tools through the command line (issue 29 item 5, balloon-assisted coiling):
# tests/host/session/data/balloon_remodelling.case (guide > balloon catheter > its wire,
# guide > microcatheter > microwire, microcatheter > coil) run by its action script in virtual
# time, replayed with every state hash checked; `session metrics --json` lists all six tools and
# `session info --json` holds them; a seventh tool is refused in one line naming file:line (exit
# 2), and the record with its version set back to 12 in one line naming byte 8 (exit 2).
#   session_cli_six_tools_test.sh BIN_DIR CASES_DIR SOURCE_DIR
source "$(dirname "$0")/session_cli_lib.sh"
data="$3/tests/host/session/data"
rec="$work/six.cbxrec"
expect 0 "$cb" session run --case "$data/balloon_remodelling.case" --script "$data/balloon_remodelling.actions" --virtual --record "$rec"
check_run six '(.unconverged_pct | keys | sort) == ["balloon", "balloon_wire", "coil", "guide", "microcatheter", "microwire"]' \
  '[.tools[].name] == ["guide", "balloon", "balloon_wire", "microcatheter", "microwire", "coil"]
   and [.tools[].inside] == ["", "guide", "balloon", "guide", "microcatheter", "microcatheter"]'
expect 0 "$cb" session replay "$rec" --check
grep -q "match" "$work/out" || fail "six-tool replay: $(cat "$work/out")"

# A seventh tool: one line naming the case file and the tool's line, exit 2.
sed "s|^vessel ../../../../cases/|vessel $cases/|" "$data/balloon_remodelling.case" >"$work/seven.case"
line=$(($(wc -l <"$work/seven.case") + 1))
printf 'tool second_wire guidewire\n  section 1800 od=0.36 ei=40 gj=31\n  inside microcatheter\nend\n' >>"$work/seven.case"
expect 2 "$cb" session run --case "$work/seven.case" --script "$data/balloon_remodelling.actions" --virtual --record "$work/seven.cbxrec"
[ "$(wc -l <"$work/out")" -eq 1 ] && grep -qx "$work/seven.case:$line: too many tools (at most 6)" "$work/out" ||
  fail "seventh tool: $(cat "$work/out")"

# The record as version 12 (its header CRC fixed up): refused in one line, exit 2.
python3 - "$rec" "$work/v12.cbxrec" <<'PY'
import struct, sys, zlib
b = bytearray(open(sys.argv[1], 'rb').read())
struct.pack_into('<H', b, 8, 12)
struct.pack_into('<I', b, 12, zlib.crc32(bytes(b[:12])))
open(sys.argv[2], 'wb').write(b)
PY
expect 2 "$cb" session replay "$work/v12.cbxrec" --check
[ "$(wc -l <"$work/out")" -eq 1 ] &&
  grep -qx "$work/v12.cbxrec: byte 8: record format version 12, this build reads version [0-9][0-9]*" "$work/out" ||
  fail "v12 record: $(cat "$work/out")"
finish

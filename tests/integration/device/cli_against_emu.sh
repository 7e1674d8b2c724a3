#!/usr/bin/env bash
# `cathbox` as a hardware engineer uses it, against a real `cathbox-emu` process: list, info,
# monitor, selftest, flash pack + flash, and the documented exit codes. No sleeps: it waits for
# the emulator's "listening" line; no timing is asserted.
set -u
bin="$1"
src="${2:-$(dirname "$0")/../../..}"
dir=$(mktemp -d)
sock="$dir/emu.sock"
failures=0
v2_pid=""
mon_pid=""
cal_pid=""
right_pid=""
exec 3< <(exec "$bin/cathbox-emu" --socket "$sock" --duration 60 2>&1)
emu_pid=$!
trap 'kill "$emu_pid" $v2_pid $mon_pid $cal_pid $right_pid 2>/dev/null; rm -rf "$dir"' EXIT
read -r line <&3
case "$line" in *listening*) ;; *) echo "emulator did not start: $line"; exit 1 ;; esac

source "$(dirname "${BASH_SOURCE[0]}")/expect.sh"

cb="$bin/cathbox"

# expect_json SHAPE COMMAND...: exit code 0 and stdout is nothing but valid JSON (parsed by jq) in
# the documented shape SHAPE (host/cli/README.md, checked by tests/host/cli/json_shape.cpp).
expect_json() {
  local shape=$1 out rc
  shift
  out=$("$@" 2>/dev/null)
  rc=$?
  if [ "$rc" -ne 0 ] || [ -z "$out" ] || ! jq -e . >/dev/null 2>&1 <<<"$out"; then
    echo "FAIL: $* -> rc $rc, not valid JSON:"
    echo "$out" | head -5
    failures=$((failures + 1))
  elif ! "$bin/cli_json_shape" "$shape" <<<"$out"; then
    echo "FAIL: $* -> not the documented --json shape '$shape'"
    failures=$((failures + 1))
  else
    echo "ok:   $* -> valid JSON, shape $shape"
  fi
}

expect 0 "emulator" -- "$cb" list --emu "$sock"
expect 0 '"board":"cathbox-emu"' -- "$cb" info --emu "$sock" --json
expect 0 "calibration  108650 counts/m" -- "$cb" info --emu "$sock"
expect 0 '"report_rate_hz"' -- "$cb" monitor --emu "$sock" --json --duration 0.5 --rate 4
expect 0 '"result":"passed"' -- "$cb" selftest --emu "$sock" --json
expect_json list "$cb" list --emu "$sock" --json
expect_json info "$cb" info --emu "$sock" --json
expect_json monitor "$cb" monitor --emu "$sock" --json --duration 0.3 --rate 10
# One line per period and the last at the end of --duration, even when it is shorter than a period
# (counted on stdout and stderr: on a loaded machine a slot may say "no state from the box").
lines=$("$cb" monitor --emu "$sock" --json --duration 1 --rate 4 2>&1 | wc -l)
short=$("$cb" monitor --emu "$sock" --json --duration 0.05 2>&1 | wc -l)
if [ "$lines" -eq 4 ] && [ "$short" -eq 1 ]; then
  echo "ok:   monitor printed 4 lines in 1 s at 4 Hz, 1 line in 0.05 s"
else
  echo "FAIL: monitor printed $lines lines in 1 s at 4 Hz (want 4), $short in 0.05 s (want 1)"
  failures=$((failures + 1))
fi
expect_json selftest "$cb" selftest --emu "$sock" --json
# calibrate --json against a second emulator whose scripted hand pushes (5 mm/s) and turns
# (1 rad/s) the tool: stdout is the documented shape (the guide goes to stderr). The guide's Enter presses come
# half a second apart so the tool travels past the minimum counts; nothing timed is asserted.
exec 6< <(exec "$bin/cathbox-emu" --socket "$dir/cal.sock" --duration 30 \
  --hand-insertion v:5mm/s:30s --hand-rotation v:1rad/s:30s 2>&1)
cal_pid=$!
read -r line <&6
out=$({ echo; sleep 0.5; echo; sleep 0.5; echo; } | "$cb" calibrate --emu "$dir/cal.sock" --json 2>/dev/null)
rc=$?
if [ "$rc" -ne 0 ] || ! "$bin/cli_json_shape" calibrate <<<"$out"; then
  echo "FAIL: calibrate --json -> rc $rc, output:"
  echo "$out" | tail -5
  failures=$((failures + 1))
else
  echo "ok:   calibrate --json -> shape calibrate"
fi
kill "$cal_pid" 2>/dev/null
expect 3 "no emulator at" -- "$cb" info --emu "$dir/none.sock"
expect 2 "unknown option --bogus" -- "$cb" info --bogus
# cathbox-emu refuses a bad option value with one line instead of running with 0 (an E-stop at
# once, seed 0, no delay); the trailing --duration bounds the run if it did not.
expect 2 "option --estop-after: bad value 'soon'" -- "$bin/cathbox-emu" --socket "$dir/bad.sock" --estop-after soon --duration 0.01
expect 2 "option --seed: bad value '12x'" -- "$bin/cathbox-emu" --socket "$dir/bad.sock" --seed 12x --duration 0.01
expect 2 "option --delay: bad value '0.1:2ms'" -- "$bin/cathbox-emu" --socket "$dir/bad.sock" --delay 0.1:2ms --duration 0.01
expect 2 "option --wire-version: bad value '2b'" -- "$bin/cathbox-emu" --socket "$dir/bad.sock" --wire-version 2b --duration 0.01
expect 2 "option --duration: bad value 'abc'" -- "$bin/cathbox-emu" --socket "$dir/bad.sock" --duration abc
# A hand script in the other axis's units (or the old bare SI numbers) is refused, not misread.
expect 2 "mm/s is an insertion unit, this script drives the rotation axis" -- "$bin/cathbox-emu" --socket "$dir/bad.sock" --hand-rotation v:30mm/s:1s --duration 0.01
expect 2 "the value has no unit" -- "$bin/cathbox-emu" --socket "$dir/bad.sock" --hand-insertion v:0.03:9s --duration 0.01
expect 2 "--duration must be in (0, 86400] s" -- "$cb" monitor --emu "$sock" --duration -1
expect 2 "--duration must be in (0, 86400] s" -- "$cb" monitor --emu "$sock" --duration 1e300
expect 2 "--timeout must be in (0, 86400] s" -- "$cb" selftest --emu "$sock" --timeout -5

# A firmware binary of version 1.1: vector table (SP in SRAM, Thumb reset vector in flash), the
# image info block at 0x200 (protocol/README.md: magic CBXI, layout 1, 64 bytes, 1.1.0 protocol
# minor 1, board, build, image size 0x6000) and a body.
{
  printf '\x00\x80\x00\x20\x01\x02\x00\x08'
  head -c $((0x200 - 8)) /dev/zero
  printf 'CBXI\x01\x40\x01\x01\x00\x01\x00\x00'
  printf 'cathbox-emu\0\0\0\0\0'
  printf 'cli-1.1'; head -c 25 /dev/zero
  printf '\x00\x60\x00\x00'
  head -c $((0x6000 - 0x240)) /dev/urandom
} > "$dir/fw.bin"
# pack takes the version from the image's info block; a --version that differs is refused
# naming both (it would make the .dfu contradict what the flashed box reports).
expect 0 "packed 24576 bytes of firmware 1.1 into" -- "$cb" flash pack "$dir/fw.bin" "$dir/fw.dfu"
expect 0 "firmware 1.1 into" -- "$cb" flash pack "$dir/fw.bin" "$dir/fw.dfu" --version 1.1
expect 2 "--version 1.0 differs from the image's own version 1.1" -- "$cb" flash pack "$dir/fw.bin" "$dir/v10.dfu" --version 1.0
expect 2 "--version 2.0 differs from the image's own version 1.1" -- "$cb" flash pack "$dir/fw.bin" "$dir/v2.dfu" --version 2.0
if [ -e "$dir/v10.dfu" ]; then echo "FAIL: a refused pack wrote $dir/v10.dfu"; failures=$((failures + 1)); fi
head -c 4096 /dev/zero > "$dir/noinfo.bin"
expect 2 "no image info block at offset 0x200" -- "$cb" flash pack "$dir/noinfo.bin" "$dir/noinfo.dfu"
expect 0 "box is back" -- "$cb" flash "$dir/fw.dfu" --emu "$sock"
cp "$dir/fw.dfu" "$dir/corrupt.dfu"
# Flip every bit of byte 1000 (the body is random: writing a fixed value would leave it as it was 1 time in 256).
byte=$(od -An -tu1 -j1000 -N1 "$dir/corrupt.dfu" | tr -d ' ')
printf "\\$(printf '%03o' $((byte ^ 0xFF)))" | dd of="$dir/corrupt.dfu" bs=1 seek=1000 conv=notrunc 2>/dev/null
cmp -s "$dir/fw.dfu" "$dir/corrupt.dfu" && { echo "FAIL: byte 1000 of corrupt.dfu unchanged"; failures=$((failures + 1)); }
expect 2 "does not match the content" -- "$cb" flash "$dir/corrupt.dfu" --emu "$sock"
expect 2 "cannot be combined" -- "$cb" flash "$dir/fw.dfu" --emu "$sock" --recover-gpio gpiochip0:17:27
expect 0 "firmware     1.1.0" -- "$cb" info --emu "$sock"

# The emulator process killed (SIGKILL, stale socket file left behind) and restarted while
# `cathbox monitor` runs: monitor's BoxClient reports the link down, then up again.
exec 5< <(exec "$cb" monitor --emu "$sock" --json --rate 50 --duration 20 2>&1)
mon_pid=$!
read -r first <&5
kill -9 "$emu_pid"
wait "$emu_pid" 2>/dev/null
down=0
while read -r line <&5; do
  case "$line" in *'"link_up":false'*) down=1; break ;; esac
done
exec 3< <(exec "$bin/cathbox-emu" --socket "$sock" --duration 60 2>&1)
emu_pid=$!
read -r line <&3
up=0
while read -r line <&5; do
  case "$line" in *'"link_up":true'*) up=1; break ;; esac
done
kill "$mon_pid" 2>/dev/null
if [ "$down" -eq 1 ] && [ "$up" -eq 1 ] && [[ "$first" == *'"link_up":true'* ]]; then
  echo "ok:   monitor saw the emulator process killed and restarted (link down, then up)"
else
  echo "FAIL: monitor across an emulator restart: first=$first down=$down up=$up"
  failures=$((failures + 1))
fi
expect 0 "emulator" -- "$cb" list --emu "$sock"

# A box from the future: the one-line message and exit code 4.
exec 4< <(exec "$bin/cathbox-emu" --socket "$dir/v2.sock" --wire-version 2 --duration 60 2>&1)
v2_pid=$!
trap 'kill "$emu_pid" $v2_pid $mon_pid $cal_pid $right_pid 2>/dev/null; rm -rf "$dir"' EXIT
read -r line <&4
expect 4 "cathbox: the box speaks protocol v2, this host speaks v1: update the host tools (or flash firmware 1.x)" -- "$cb" info --emu "$dir/v2.sock"
expect 4 "speaks protocol v2" -- "$cb" monitor --emu "$dir/v2.sock" --duration 0.1

# Two boxes on one rig: each listed by its serial; a session with a box per tool (two emulators
# it starts, EMU-0001 for the catheter, EMU-0002 for the guidewire); bad bindings: one line, exit 2.
exec 6< <(exec "$bin/cathbox-emu" --socket "$dir/right.sock" --serial EMU-RIGHT --duration 60 2>&1)
right_pid=$!
read -r line <&6
expect 0 "emulator    $dir/right.sock  serial EMU-RIGHT" -- "$cb" list --emu "$sock" --emu "$dir/right.sock"
expect 0 "emulator    $sock  serial EMU-0001" -- "$cb" list --emu "$sock" --emu "$dir/right.sock"
expect_json list "$cb" list --emu "$sock" --emu "$dir/right.sock" --json
expect 0 "2 boxes: catheter <- serial EMU-0001" -- "$cb" session run --case "$src/cases/neuro.case" --record "$dir/two.cbxrec" \
  --box catheter=emu --box guidewire=emu --seconds 0.3
expect 0 "guidewire <- serial EMU-RIGHT" -- "$cb" session run --case "$src/cases/neuro.case" --record "$dir/two2.cbxrec" \
  --box catheter=emu:"$sock" --box guidewire=emu:"$dir/right.sock" --seconds 0.3
expect 2 "--box: two boxes for 'catheter'" -- "$cb" session run --case "$src/cases/neuro.case" --record "$dir/x.cbxrec" \
  --box catheter=emu --box catheter=emu
expect 2 "the case has no tool 'coil' (its tools: catheter, guidewire)" -- "$cb" session run --case "$src/cases/neuro.case" \
  --record "$dir/x.cbxrec" --box coil=emu --box guidewire=emu
expect 3 "box for 'catheter': no box with serial 'CBX-9999'" -- "$cb" session run --case "$src/cases/neuro.case" \
  --record "$dir/x.cbxrec" --box catheter=CBX-9999 --box guidewire=emu

[ "$failures" -eq 0 ] || { echo "$failures check(s) failed"; exit 1; }
echo "all cathbox CLI checks passed against cathbox-emu"

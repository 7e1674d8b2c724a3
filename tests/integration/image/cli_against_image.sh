#!/usr/bin/env bash
# `cathbox` against a real `cathbox-emu --image` process running the cross-built STM32F411
# image: info reports the image's own version and board, monitor streams, `cathbox flash`
# goes through the image's bootloader request and comes back; the packed .dfu runs as the .bin
# does (a corrupt one refused); --trace-mmio names
# registers; a missing or unbootable image is refused with one line (exit 2). No sleeps: it
# waits for the emulator's "enumerated" line; no timing is asserted.
set -u
bin="$1"
image="${2:-${CATHBOX_FIRMWARE_IMAGE:-}}"
dir=$(mktemp -d)
sock="$dir/image.sock"
failures=0
[ -f "$image" ] || { echo "no firmware image at '$image' (scripts/build stm32f411)"; exit 1; }
# wait_enumerated FD: reads the emulator's output on FD until it says the image enumerated.
wait_enumerated() {
  local line
  while read -r line <&"$1"; do
    case "$line" in *"the image enumerated"*) return 0 ;; *stopped*|*"cannot"*) echo "$line"; return 1 ;; esac
  done
  return 1
}
exec 3< <(exec "$bin/cathbox-emu" --image "$image" --socket "$sock" --duration 60 2>&1)
emu_pid=$!
dfu_pid=
trap 'kill "$emu_pid" $dfu_pid 2>/dev/null; rm -rf "$dir"' EXIT
wait_enumerated 3 || { echo "FAIL: the image did not enumerate"; exit 1; }

source "$(dirname "${BASH_SOURCE[0]}")/../device/expect.sh"
cases="$(dirname "${BASH_SOURCE[0]}")/../../../cases"

# The version the image's info block says (offset 0x200: magic, layout, size, major, minor, patch).
version=$(od -An -tu1 -j $((0x206)) -N 3 "$image" | awk '{print $1 "." $2 "." $3}')
expect 0 "board        stm32f411-bp" -- "$bin/cathbox" info --emu "$sock"
expect 0 "firmware     $version" -- "$bin/cathbox" info --emu "$sock"
expect 0 "not-calibrated" -- "$bin/cathbox" monitor --emu "$sock" --duration 0.2 --rate 10
# The image's own self-test (test drive, currents through its ADC): the factory image fails on
# calibration alone (exit 1); a session refuses the uncalibrated box (exit 3).
expect 1 "failed checks   calibration" -- "$bin/cathbox" selftest --emu "$sock"
expect 3 "is not calibrated (run 'cathbox calibrate')" -- "$bin/cathbox" session run --case "$cases/neuro.case" \
  --record "$dir/s.cbxrec" --emu "$sock" --seconds 0.2
# cathbox flash through the image: feature 0x14, its reset into the ROM (the emulated DfuSe
# bootloader), erase, download, verify, leave; the new image boots and reports its info block.
expect 0 "packed" -- "$bin/cathbox" flash pack "$image" "$dir/fw.dfu"
expect 0 "box is back: firmware $version" -- "$bin/cathbox" flash "$dir/fw.dfu" --emu "$sock"
cp "$dir/fw.dfu" "$dir/corrupt.dfu"
printf '\x00' | dd of="$dir/corrupt.dfu" bs=1 seek=1000 conv=notrunc 2>/dev/null
expect 2 "does not match the content" -- "$bin/cathbox" flash "$dir/corrupt.dfu" --emu "$sock"
expect 0 "board        stm32f411-bp" -- "$bin/cathbox" info --emu "$sock"
expect 0 "W RCC.CR @0x40023800" -- "$bin/cathbox-emu" --image "$image" --socket "$dir/trace.sock" --trace-mmio --duration 0.01
expect 2 "cannot read image $dir/none.bin" -- "$bin/cathbox-emu" --image "$dir/none.bin" --socket "$dir/x.sock" --duration 0.01
head -c 4096 /dev/zero > "$dir/zero.bin"
# The .dfu that `cathbox flash pack` wrote runs as the .bin does (here on a board whose crystal
# never starts: the image falls back to HSI and info reports the board fault); a corrupt one is
# refused naming the byte of its suffix CRC.
# It is calibrated at start (--calibrated: the model's calibration through the image's own
# calibration report and flash store): its self-test passes, and the trainer's session run
# against it replays with every state hash matching.
exec 4< <(exec "$bin/cathbox-emu" --image "$dir/fw.dfu" --crystal-fails --calibrated --socket "$dir/dfu.sock" --duration 60 2>&1)
dfu_pid=$!
if wait_enumerated 4; then
  expect 0 "firmware     $version" -- "$bin/cathbox" info --emu "$dir/dfu.sock"
  expect 0 "board faults hse: the crystal did not start" -- "$bin/cathbox" info --emu "$dir/dfu.sock"
  expect 0 "self-test PASSED" -- "$bin/cathbox" selftest --emu "$dir/dfu.sock"
  expect 0 "contrast volume" -- "$bin/cathbox" session run --case "$cases/neuro.case" --record "$dir/image.cbxrec" \
    --emu "$dir/dfu.sock" --seconds 0.5
  expect 0 "every state hash matches" -- "$bin/cathbox" session replay "$dir/image.cbxrec" --check
else
  echo "FAIL: cathbox-emu --image fw.dfu did not enumerate"
  failures=$((failures + 1))
fi
kill "$dfu_pid" 2>/dev/null
# `cathbox calibrate` against the image, whose scripted hand pushes (5 mm/s) and turns (1 rad/s)
# the tool: it writes the calibration and reads it back at once while the image saves it to
# its flash store (exit 0); the box then reports itself calibrated. The guide's Enter presses
# come half a second apart so the tool travels past the minimum counts; nothing timed is asserted.
# The fault options apply to the image too: a fifth of its state reports arrive with a bit
# flipped, which the host refuses (monitor's host_rejected) while calibrate still succeeds.
exec 5< <(exec "$bin/cathbox-emu" --image "$image" --socket "$dir/cal.sock" --duration 60 \
  --hand-insertion v:5mm/s:60s --hand-rotation v:1rad/s:60s --corrupt 0.2 --seed 7 2>&1)
dfu_pid=$!
if wait_enumerated 5; then
  out=$({ echo; sleep 0.5; echo; sleep 0.5; echo; } | "$bin/cathbox" calibrate --emu "$dir/cal.sock" \
    --full-scale-mN 5000 --full-scale-uNm 50000 2>&1)
  rc=$?
  if [ "$rc" -ne 0 ] || ! grep -q "written: " <<<"$out"; then
    echo "FAIL: calibrate against the image -> rc $rc, output:"
    echo "$out" | tail -3
    failures=$((failures + 1))
  else
    echo "ok:   calibrate against the image -> $(grep -o 'written: .*' <<<"$out")"
  fi
  expect 0 "full scale 5000 mN, 50000 uN*m" -- "$bin/cathbox" info --emu "$dir/cal.sock"
  if "$bin/cathbox" monitor --emu "$dir/cal.sock" --json --duration 0.3 --rate 10 | grep -qE '"host_rejected": ?[1-9]'; then
    echo "ok:   monitor against the image with --corrupt 0.2 -> corrupted reports refused"
  else
    echo "FAIL: monitor against the image with --corrupt 0.2 -> no refused report"
    failures=$((failures + 1))
  fi
else
  echo "FAIL: cathbox-emu --image (calibrate) did not enumerate"
  failures=$((failures + 1))
fi
kill "$dfu_pid" 2>/dev/null
crc_at=$(( $(stat -c %s "$dir/corrupt.dfu") - 4 ))
expect 2 "corrupt.dfu: byte $crc_at: suffix CRC" -- "$bin/cathbox-emu" --image "$dir/corrupt.dfu" --socket "$dir/x.sock" --duration 0.01
expect 2 "no bootable vector table" -- "$bin/cathbox-emu" --image "$dir/zero.bin" --socket "$dir/x.sock" --duration 0.01
[ "$failures" -eq 0 ] || { echo "$failures failed"; exit 1; }
echo "all passed"

#!/usr/bin/env bash
# The cathbox Debian package (the trainer, the cathbox tool, the emulated box and its bridge),
# built by CPack from this build and checked once: lintian with no errors; its files unpacked
# into a throwaway root (dpkg -x): `cathbox --version` and every program's --help from usr/bin,
# a manual page per program that renders, the bundled cases, the udev rule (check_udev_rule.sh,
# against the VID:PIDs protocol/README.md names) and the desktop entry (desktop-file-validate).
# Usage: check_cathbox_package.sh BUILD_DIR OUT_DIR SOURCE_DIR
set -euo pipefail
build=$1
out=$2
source_dir=$3
here=$(dirname "${BASH_SOURCE[0]}")
source "$here/lib.sh"
make_packages "$build" "$out" app
deb=$(ls "$out"/cathbox_*.deb)
echo "package: $deb"
lintian_clean "$deb"

root=$out/root
dpkg-deb -x "$deb" "$root"
version=$(sed -n 's/^project(cathbox VERSION \([0-9.]*\).*/\1/p' "$source_dir/CMakeLists.txt")
said=$("$root/usr/bin/cathbox" --version)
[ "$said" = "cathbox $version" ] || { echo "FAIL: usr/bin/cathbox --version says '$said', not 'cathbox $version'"; exit 1; }
for program in cathbox-trainer cathbox cathbox-emu cathbox-box-bridge; do
  "$root/usr/bin/$program" --help >"$out/$program.help" || { echo "FAIL: usr/bin/$program --help: exit $?"; exit 1; }
  page=$root/usr/share/man/man1/$program.1.gz
  MANWIDTH=200 man -l "$page" 2>&1 | grep -q "$program - " || { echo "FAIL: the manual page $page does not render"; exit 1; }
  ! zcat "$page" | grep -qF "$source_dir" || { echo "FAIL: $page names the source folder $source_dir"; exit 1; }
  first=$(grep -m 1 -v '^$' "$out/$program.help")
  MANWIDTH=200 man -l "$page" 2>/dev/null | grep -qF -- "${first:0:40}" || { echo "FAIL: $page does not hold --help ('${first:0:40}')"; exit 1; }
done
[ -f "$root/usr/share/cathbox/cases/neuro_right_ica.case" ] || { echo "FAIL: the trainer's default case is not in usr/share/cathbox/cases"; exit 1; }

rule=$root/usr/lib/udev/rules.d/70-cathbox.rules
ids=$(grep -oE '^\| VID:PID \([a-z]+\) \| `[0-9A-Fa-f]{4}:[0-9A-Fa-f]{4}`' "$source_dir/protocol/README.md" | grep -oE '[0-9A-Fa-f]{4}:[0-9A-Fa-f]{4}')
[ "$(echo "$ids" | wc -l)" -eq 2 ] || { echo "FAIL: protocol/README.md does not name the application's and the bootloader's VID:PID"; exit 1; }
# shellcheck disable=SC2086  # one argument per VID:PID
bash "$here/check_udev_rule.sh" "$rule" $ids || { echo "FAIL: the udev rule $rule"; exit 1; }

desktop=$root/usr/share/applications/cathbox-trainer.desktop
desktop-file-validate "$desktop" || { echo "FAIL: desktop-file-validate $desktop"; exit 1; }
grep -qx 'Exec=cathbox-trainer' "$desktop" || { echo "FAIL: $desktop does not start cathbox-trainer"; exit 1; }
echo "ok: $(basename "$deb"): lintian clean of errors, --version and --help, manual pages, cases, udev rule ($ids), desktop entry" | tr '\n' ' '
echo

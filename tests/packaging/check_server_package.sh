#!/usr/bin/env bash
# The cathbox-server Debian package, built by CPack from this build and checked once:
#   lintian with no errors; its files unpacked into a throwaway root (dpkg -x): the program
#   answers --help from usr/bin, the admin wrapper and the maintainer scripts are valid sh, the
#   systemd unit passes `systemd-analyze verify` and carries the sandboxing it promises, and the
#   manual page renders.
# Usage: check_server_package.sh BUILD_DIR OUT_DIR
set -euo pipefail
build=$1
out=$2
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
make_packages "$build" "$out" server
mkdir -p "$out/root"
deb=$(ls "$out"/cathbox-server_*.deb)
echo "package: $deb"
lintian_clean "$deb"

dpkg-deb -x "$deb" "$out/root"
dpkg-deb -e "$deb" "$out/control"
root=$out/root
"$root/usr/bin/cathbox-server" --help >"$out/help.txt"
grep -q -- '--tls-cert' "$out/help.txt" || { echo "FAIL: usr/bin/cathbox-server --help does not list --tls-cert"; exit 1; }
for script in "$root/usr/sbin/cathbox-server-admin" "$out/control/postinst" "$out/control/prerm" "$out/control/postrm"; do
  sh -n "$script" || { echo "FAIL: $script is not valid sh"; exit 1; }
done
grep -qx /etc/default/cathbox-server "$out/control/conffiles" || { echo "FAIL: /etc/default/cathbox-server is not a conffile"; exit 1; }

unit=$root/usr/lib/systemd/system/cathbox-server.service
for line in User=cathbox StateDirectory=cathbox-server ProtectSystem=strict NoNewPrivileges=yes \
            ReadWritePaths=/var/lib/cathbox-server 'ExecReload=/bin/kill -HUP $MAINPID'; do
  grep -qxF "$line" "$unit" || { echo "FAIL: the unit lacks '$line'"; exit 1; }
done
# verify resolves ExecStart: point it at the unpacked program.
sed "s|/usr/bin/cathbox-server|$root/usr/bin/cathbox-server|" "$unit" >"$out/cathbox-server.service"
if ! SYSTEMD_LOG_LEVEL=warning systemd-analyze verify --man=no "$out/cathbox-server.service" >"$out/verify.log" 2>&1; then
  cat "$out/verify.log"
  echo "FAIL: systemd-analyze verify"
  exit 1
fi
grep -v -e 'Failed to connect' -e 'No such file or directory' "$out/verify.log" || true

man -l "$root/usr/share/man/man1/cathbox-server.1.gz" 2>&1 | grep -q 'cathbox-server - the Cathbox training centre server' ||
  { echo "FAIL: the manual page does not render"; exit 1; }
echo "ok: $(basename "$deb"): lintian clean of errors, --help, unit verified, manual page"

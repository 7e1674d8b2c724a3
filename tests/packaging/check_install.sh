#!/usr/bin/env bash
# The three Debian packages installed as on a fresh training-centre machine, without touching
# this one: in a private mount namespace an overlay makes a copy-on-write copy of / (its writes
# land in OUT_DIR/upper), with empty /tmp, /run (no systemd there: the maintainer scripts do not
# reach this machine's service manager) and source tree (a fresh machine has none: the trainer
# must find its cases in /usr/share). In that copy, through chroot:
#   - `dpkg -i` of cathbox, cathbox-server and cathbox-firmware (their dependencies are this
#     machine's packages) runs the maintainer scripts (the cathbox system user, the unit enabled);
#   - `cathbox --version` and `cathbox-server --help` from /usr/bin; the packaged .dfu boots on
#     the emulated STM32F411 (cathbox-emu --image) and its .bin is the image built;
#   - a throwaway CA made with `openssl`, its certificate in /etc/cathbox-server, named in
#     /etc/default/cathbox-server; an account made with cathbox-server-admin; the unit's own
#     ExecStart run as its user on its state directory; the trainer refuses the server without
#     the CA (one line, the run queued) and logs in, runs the default case and uploads with
#     --ca-file;
#   - `dpkg --purge` of the three: the user, the unit's enablement and every packaged file are
#     gone, the state directory (the database) stays, and the copy's changes outside it are only
#     dpkg's and the account files' own bookkeeping.
# It needs root and mount namespaces (overlay, chroot); without them: one line, exit 77 (CTest:
# skipped). 22-33 s on the 2 shared cores (ctest --preset release -R package_install).
# Usage: check_install.sh BUILD_DIR OUT_DIR FIRMWARE_BIN
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [ "${1:-}" = --inside ]; then
  inside=1
  shift
fi
build=$(cd "$1" && pwd)
out=$2
image=$3
source_dir=$(cd "$here/../.." && pwd)
source "$here/lib.sh"

if [ -z "${inside:-}" ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "SKIP: installing into a copy of this machine needs root (overlay mount, chroot)"
    exit 77
  fi
  unshare --mount true 2>/dev/null || { echo "SKIP: this machine allows no private mount namespace (unshare --mount)"; exit 77; }
  [ -f "$image" ] || { echo "FAIL: no firmware image at $image (scripts/build stm32f411)"; exit 1; }
  rm -rf "$out"
  make_packages "$build" "$out/debs" app server firmware
  firmware_deb=$(ls "$out"/debs/cathbox-firmware_*_all.deb)
  lintian_clean "$firmware_deb"
  mkdir -p "$out/upper" "$out/work" "$out/merged"
  exec unshare --mount --propagation private bash "${BASH_SOURCE[0]}" --inside "$build" "$out" "$image"
fi

m=$out/merged
mount -t overlay overlay -o "lowerdir=/,upperdir=$out/upper,workdir=$out/work" "$m"
mount --rbind /dev "$m/dev"
mount -t proc proc "$m/proc"
mount -t tmpfs tmpfs "$m/tmp"
mount -t tmpfs tmpfs "$m/run"
mount -t tmpfs tmpfs "$m$source_dir"
in_root() { chroot "$m" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 "$@"; }
fail() {
  echo "FAIL: $1"
  exit 1
}

# Install.
mkdir "$m/tmp/debs"
cp "$out"/debs/*.deb "$m/tmp/debs/"
in_root sh -c 'dpkg -i /tmp/debs/*.deb' >"$out/dpkg-install.log" 2>&1 || { tail -n 20 "$out/dpkg-install.log"; fail "dpkg -i"; }
for package in cathbox cathbox-server cathbox-firmware; do
  in_root dpkg-query -W -f '${Status}\n' "$package" | grep -qx 'install ok installed' || fail "$package is not installed"
done
version=$(dpkg-deb -f "$(ls "$out"/debs/cathbox_*.deb)" Version)
said=$(in_root /usr/bin/cathbox --version)
[ "$said" = "cathbox ${version%-*}" ] || fail "/usr/bin/cathbox --version says '$said', not 'cathbox ${version%-*}'"
in_root /usr/bin/cathbox-server --help | grep -q -- '--tls-cert' || fail "/usr/bin/cathbox-server --help does not list --tls-cert"
in_root getent passwd cathbox >/dev/null || fail "the postinst made no cathbox user"
[ -L "$m/etc/systemd/system/multi-user.target.wants/cathbox-server.service" ] || fail "the postinst did not enable the unit"

# The firmware: the image built, and its DfuSe file boots on the emulated chip.
fw=/usr/share/cathbox-firmware
cmp -s "$image" "$m$fw/stm32f411_firmware.bin" || fail "$fw/stm32f411_firmware.bin is not $image"
in_root /usr/bin/cathbox-emu --image "$fw/stm32f411_firmware.dfu" --socket /tmp/fw.sock --duration 0.01 >"$out/emu.log" 2>&1 ||
  { cat "$out/emu.log"; fail "cathbox-emu --image $fw/stm32f411_firmware.dfu"; }

# The service's program with a certificate from a throwaway CA, as the unit starts it.
certs=$m/etc/cathbox-server
mkdir -p "$certs"
ssl() { openssl "$@" >>"$out/openssl.log" 2>&1 || fail "openssl $1 (see $out/openssl.log)"; }
ssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -keyout "$out/ca.key" -out "$certs/ca.pem" \
  -subj /CN=throwaway-centre-ca -days 2
ssl req -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -keyout "$certs/server.key" -out "$out/server.csr" -subj /CN=centre
printf 'subjectAltName=IP:127.0.0.1\nbasicConstraints=CA:FALSE\nextendedKeyUsage=serverAuth\n' >"$out/server.ext"
ssl x509 -req -in "$out/server.csr" -CA "$certs/ca.pem" -CAkey "$out/ca.key" -CAcreateserial -out "$certs/server.pem" \
  -days 2 -extfile "$out/server.ext"
in_root chown root:cathbox /etc/cathbox-server/server.key
chmod 640 "$certs/server.key"
echo 'CATHBOX_SERVER_ARGS="--listen 127.0.0.1:0 --tls-cert /etc/cathbox-server/server.pem --tls-key /etc/cathbox-server/server.key"' \
  >>"$m/etc/default/cathbox-server"
# What systemd does for StateDirectory= and User=, then the unit's ExecStart.
in_root install -d -o cathbox -g cathbox -m 700 /var/lib/cathbox-server
echo 'password-123' | in_root /usr/sbin/cathbox-server-admin create-user ann --role trainee >"$out/admin.log" 2>&1 ||
  { cat "$out/admin.log"; fail "cathbox-server-admin create-user"; }
exec_start=$(sed -n 's/^ExecStart=//p' "$m/usr/lib/systemd/system/cathbox-server.service")
exec 3< <(exec chroot "$m" /usr/bin/env -i PATH=/usr/bin:/bin setpriv --reuid=cathbox --regid=cathbox --init-groups -- \
  sh -c ". /etc/default/cathbox-server; exec $exec_start" 2>&1)
server_pid=$!
trap 'kill "$server_pid" 2>/dev/null || true' EXIT
port=
while IFS= read -r -t 30 -u 3 line; do
  echo "$line" >>"$out/server.log"
  if [[ "$line" =~ listening\ on\ https://127\.0\.0\.1:([0-9]+) ]]; then
    port=${BASH_REMATCH[1]}
    break
  fi
done
[ -n "$port" ] || { cat "$out/server.log"; fail "the service's program did not listen over HTTPS"; }
cat <&3 >>"$out/server.log" &

mkdir -p "$m/tmp/rig"
echo 'password-123' >"$m/tmp/rig/password"
trainer() {
  in_root env HOME=/tmp/rig XDG_CONFIG_HOME=/tmp/rig/config XDG_DATA_HOME=/tmp/rig/data XDG_CACHE_HOME=/tmp/rig/cache \
    /usr/bin/cathbox-trainer --headless --no-box --seconds 0.3 --server "https://127.0.0.1:$port" --user ann \
    --password-file /tmp/rig/password --rig rig-1 "$@" >"$out/trainer.log" 2>&1 || { cat "$out/trainer.log"; fail "cathbox-trainer $*"; }
}
expect_said() { grep -qF -- "$1" "$out/trainer.log" || { cat "$out/trainer.log"; fail "the trainer did not say '$1'"; }; }
trainer
expect_said "TLS to 127.0.0.1:$port: certificate verify failed"
expect_said "upload: 0 stored, 0 already on the server, 0 refused, 1 queued"
trainer --ca-file /etc/cathbox-server/ca.pem
expect_said "online as ann, rig rig-1, 0 assignments"
expect_said "headless run of neuro: right internal carotid"
expect_said "upload: 2 stored, 0 already on the server, 0 refused, 0 queued"
kill "$server_pid"
wait "$server_pid" 2>/dev/null || true
[ -s "$m/var/lib/cathbox-server/server.db" ] || fail "the service kept no database in /var/lib/cathbox-server"

# Purge: the administrator's certificates are theirs to remove; then only the state directory
# and the system's own bookkeeping may be left in the copy.
rm -rf "$certs"
in_root dpkg --purge cathbox cathbox-server cathbox-firmware >"$out/dpkg-purge.log" 2>&1 || { tail -n 20 "$out/dpkg-purge.log"; fail "dpkg --purge"; }
in_root getent passwd cathbox >/dev/null && fail "the cathbox user is still there after purge"
for file in passwd group shadow gshadow subuid subgid; do
  cmp -s "/etc/$file" "$m/etc/$file" || fail "/etc/$file differs from before the install"
done
left=$(cd "$out/upper" && find . -not -type d |
  grep -vE '^\./(var/lib/dpkg/|var/log/|var/cache/(man|debconf)/|etc/(passwd|group|shadow|gshadow|subuid|subgid)-?$|etc/\.pwd\.lock$|etc/mailcap$|usr/share/applications/mimeinfo\.cache$|var/lib/cathbox-server/)' || true)
left+=$(cd "$out/upper" && find . -type d -name '*cathbox*' -not -path './var/lib/cathbox-server*')
[ -z "$left" ] || { echo "$left"; fail "the purge left these behind"; }
[ -s "$m/var/lib/cathbox-server/server.db" ] || fail "the purge removed the state directory"
echo "ok: installed, served over TLS (throwaway CA) to the trainer's login from /usr/bin, purged: only /var/lib/cathbox-server stays"

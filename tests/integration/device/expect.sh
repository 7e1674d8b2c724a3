# Sourced by the CLI shell tests (cli_against_emu.sh, ../image/cli_against_image.sh); counts
# failures in the caller's $failures.
# expect RC NEEDLE -- COMMAND...: the exit code must be RC and the output must contain NEEDLE.
expect() {
  local want_rc=$1 needle=$2
  shift 3
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if [ "$rc" -ne "$want_rc" ] || [[ "$out" != *"$needle"* ]]; then
    echo "FAIL: $* -> rc $rc (want $want_rc), output:"
    echo "$out" | head -20
    failures=$((failures + 1))
  else
    echo "ok:   $* -> rc $rc"
  fi
}

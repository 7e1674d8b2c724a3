# Sourced by the command-line test scripts: `cathbox="$1" src="$2" work="$3"` from the script's
# arguments, a fresh $work, and the helpers
#   fail MESSAGE          counts a failure
#   expect CODE CMD...    runs CMD, checks its exit code; stdout/stderr land in $work/out, $work/err
#   json_shape SHAPE      checks $work/out against a documented --json shape (cli_json_shape,
#                         beside the cathbox executable; tests/host/cli/json_shape.cpp)
#   finish NAME           prints the verdict and exits 1 on failures
set -u
cathbox="$1"
src="$2"
work="$3"
rm -rf "$work"
mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

expect() {
  local want="$1"
  shift
  "$@" >"$work/out" 2>"$work/err"
  local got=$?
  [ "$got" -eq "$want" ] || fail "exit $got (want $want): $* -- $(head -c 300 "$work/err")"
}

json_shape() {
  "$(dirname "$cathbox")/cli_json_shape" "$1" <"$work/out" 2>"$work/shape" ||
    fail "--json shape $1: $(head -c 300 "$work/shape")"
}

finish() {
  if [ "$failures" -ne 0 ]; then
    echo "$failures failure(s)" >&2
    exit 1
  fi
  echo "$1: all checks passed"
}

# Sourced by session_cli_test.sh and session_cli_coiling_test.sh: `bin="$1" cases="$2"` from the
# script's arguments, a fresh $work (removed at exit, with the processes in $emu_pid $run_pid),
# and the helpers
#   fail MESSAGE           counts a failure
#   expect RC COMMAND...   runs COMMAND, checks its exit code; its output lands in $work/out
#   shape NAME             checks $work/out against a documented --json shape (json_shape.cpp)
#   check_run NAME M I     the record $rec's metrics (shape-checked) and info as JSON against the
#                          jq filters M and I
#   finish                 prints the verdict and exits 1 on failures
set -u
bin="$1"
cases="$2"
cb="$bin/cathbox"
work=$(mktemp -d)
emu_pid=""
run_pid=""
trap 'kill $emu_pid $run_pid 2>/dev/null; rm -rf "$work"' EXIT
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

expect() {
  local want=$1
  shift
  "$@" >"$work/out" 2>&1
  local rc=$?
  if [ "$rc" -ne "$want" ]; then
    fail "$* -> rc $rc (want $want): $(head -5 "$work/out")"
    return 1
  fi
  echo "ok:   $* -> rc $rc"
}

shape() { "$bin/cli_json_shape" "$1" <"$work/out" || fail "--json shape $1: $(head -c 300 "$work/out")"; }

check_run() {
  expect 0 "$cb" session metrics "$rec" --json
  shape session-metrics
  jq -e "$2" "$work/out" >/dev/null || fail "$1 metrics: $(cat "$work/out")"
  expect 0 "$cb" session info "$rec" --json
  jq -e "$3" "$work/out" >/dev/null || fail "$1 info: $(cat "$work/out")"
}

finish() {
  if [ "$failures" -ne 0 ]; then
    echo "$failures failure(s)"
    exit 1
  fi
  echo "all passed"
}

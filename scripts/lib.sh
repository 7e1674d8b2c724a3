# Shared by the scripts: repo root, presets, logging.
set -euo pipefail
CATHBOX_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export CATHBOX_ROOT
# Every line says how long since the first script of this run started (scripts/test calls the
# others: the CI log then shows where the time goes, step by step).
CATHBOX_T0="${CATHBOX_T0:-$(date +%s)}"
export CATHBOX_T0
cathbox_log() { printf '==> [%5d s] %s\n' "$(( $(date +%s) - CATHBOX_T0 ))" "$*" >&2; }
cathbox_jobs() { nproc 2>/dev/null || echo 2; }

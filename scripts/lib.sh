# Shared by the scripts: repo root, presets, logging.
set -euo pipefail
CATHBOX_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export CATHBOX_ROOT
cathbox_log() { printf '==> %s\n' "$*" >&2; }
cathbox_jobs() { nproc 2>/dev/null || echo 2; }

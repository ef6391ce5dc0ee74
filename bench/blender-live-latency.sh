#!/usr/bin/env bash
# The live sky's latency in a real Blender window (Debian's 3.4 under Xvfb; bench/blender_live_latency.py
# says what it measures), recorded in docs/performance/blender-live.md (bench/record-run.sh).
# Usage: bench/blender-live-latency.sh [N changes of each kind, default 12] [WIDTH, default 512] [BOUND_MS]
# (after a build; BOUND_MS: another bound than the add-on's, see the .py)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
log=$(mktemp)
trap 'rm -f "$log" "$log.all"' EXIT
"$ROOT/tests/blender/run_window.sh" "$ROOT/bench/blender_live_latency.py" "$ROOT/build/firmament_sky.zip" \
    "$ROOT/build/firmament" "${1:-12}" "${2:-512}" ${3:+"$3"} 2>&1 | tee "$log.all"
grep -E '^(Blender|first map|change|  )' "$log.all" >"$log" || true
grep -q -- '-> image reloaded' "$log" || { echo "blender-live-latency: no figures (see above)" >&2; exit 1; }
"$ROOT/bench/record-run.sh" blender-live "$log"

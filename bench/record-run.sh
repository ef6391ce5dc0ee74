#!/usr/bin/env bash
# bench/record-run.sh MODE LOG: adds one benchmark run, as bench/bench.sh printed it (LOG), at the top
# of docs/performance/MODE.md with its date, machine and code revision; bench.sh calls it after a
# run that finished.  Figures are never written there by hand.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mode=${1:?MODE}
log=${2:?LOG}
file="$ROOT/docs/performance/$mode.md"
marker='<!-- bench.sh adds each run below this line, newest first -->'
if [ ! -f "$file" ]; then
    flag=$([ "$mode" = speed ] && echo "" || echo " --$mode")
    {
        echo "# Benchmark runs: bench/bench.sh$flag"
        echo
        echo "Written by \`bench/bench.sh$flag\` at the end of each run that finished (what each column"
        echo "measures: the comment at the top of [bench/bench.sh](../../bench/bench.sh)).  Compare runs of one"
        echo "machine only."
        echo
        echo "$marker"
    } >"$file"
    # the folder's list (docs/performance/README.md) links the file from now on
    list="$ROOT/docs/performance/README.md"
    sed "s/^| \`$mode\.md\` (no run recorded yet) |/| [$mode.md]($mode.md) |/" "$list" >"$list.new"
    mv "$list.new" "$list"
fi
revision=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)
git -C "$ROOT" diff --quiet HEAD -- core 2>/dev/null || revision="$revision with uncommitted changes to core/"
cpu=$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2 | sed 's/^ //')
section=$(mktemp)
trap 'rm -f "$section"' EXIT
{
    echo
    echo "## $(date -u '+%Y-%m-%d %H:%M UTC'): ${cpu:-$(uname -m)}, $(nproc) threads, code $revision"
    echo
    echo '```'
    cat "$log"
    echo '```'
} >"$section"
awk -v marker="$marker" -v section="$section" '
    { print }
    $0 == marker { while ((getline line < section) > 0) print line }
' "$file" >"$file.new"
mv "$file.new" "$file"
echo "recorded in ${file#"$ROOT"/}"

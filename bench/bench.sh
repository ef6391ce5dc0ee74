#!/usr/bin/env bash
# Benchmark of the default (fast) path: for the default sky (sun 30 degrees) and a sunset (sun 2),
# renders a 1024 x 512 map at the default quality, then the same sky with 16 times the samples
# (--sample-scale 16), and prints wall time, peak memory and the relative luminance error of the
# first against the second (RMS and 99th percentile over all pixels; the sun disk is left out by
# rendering with --no-sun-disk, its aureole stays in).
#   bench/bench.sh [WIDTH]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
. "$ROOT/scripts/common.sh"
install_missing_packages
build build >/dev/null
FM="$ROOT/build/firmament"
WIDTH=${1:-1024}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

field() { sed -n "s/.*\"$1\": \([0-9.eE+-]*\).*/\1/p" | tail -n 1; }

run() { # name, extra args... -> prints "seconds peak_mib"
    local name=$1
    shift
    "$FM" render --width "$WIDTH" --no-sun-disk --progress json -o "$out/$name.exr" "$@" >"$out/$name.log"
    echo "$(field seconds <"$out/$name.log") $(field peak_memory_mib <"$out/$name.log")"
}

echo "firmament $("$FM" --version | cut -d' ' -f2), $(nproc) threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
printf '%-22s %-10s %-8s %9s %9s %9s %9s %12s\n' sky size quality "wall s" "peak MiB" "RMS %" "p99 %" "16x wall s"
for sky in "default (sun 30):--sun-elevation 30" "sunset (sun 2):--sun-elevation 2"; do
    name=${sky%%:*}
    args=${sky#*:}
    tag=$(echo "$name" | cut -d' ' -f1)
    read -r sec mem <<<"$(run "$tag" $args)"
    read -r sec16 _ <<<"$(run "$tag-16x" $args --sample-scale 16)"
    cmp=$("$FM" compare "$out/$tag.exr" "$out/$tag-16x.exr" --json)
    rms=$(echo "$cmp" | field rms)
    p99=$(echo "$cmp" | field p99)
    printf '%-22s %-10s %-8s %9.2f %9.0f %9.3f %9.3f %12.2f\n' "$name" "${WIDTH}x$((WIDTH / 2))" final "$sec" "$mem" \
        "$(awk -v x="$rms" 'BEGIN { print 100 * x }')" "$(awk -v x="$p99" 'BEGIN { print 100 * x }')" "$sec16"
done

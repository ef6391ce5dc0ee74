#!/usr/bin/env bash
# Benchmark of the default (fast) path.  For each sky, renders a map at the default quality, then
# the same sky with 16 times the samples (--sample-scale 16), and prints wall time, peak memory and
# the relative luminance error of the first against the second (RMS and 99th percentile over all
# pixels; the sun disk is left out by rendering with --no-sun-disk, its aureole stays in).
#
# "cost x" is the wall time relative to the clear sky (no aerosol) at equal RMS error: Monte Carlo
# error falls as 1/sqrt(samples), so equal error costs wall * (RMS / RMS_clear)^2.
#   bench/bench.sh [WIDTH]           clear sky, default sky (rural), sunset (urban, turbidity 2)
#   bench/bench.sh --biomes [WIDTH]  the same, then every biome with the sun at 30 degrees
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
. "$ROOT/scripts/common.sh"
install_missing_packages
build build >/dev/null
FM="$ROOT/build/firmament"
BIOMES=0
if [ "${1:-}" = "--biomes" ]; then BIOMES=1; shift; fi
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

clear_cost=""
bench_sky() { # label, args...
    local name=$1
    shift
    local tag
    tag=$(echo "$name" | tr -c 'a-z0-9\n' '_')
    read -r sec mem <<<"$(run "$tag" "$@")"
    read -r sec16 _ <<<"$(run "$tag-16x" "$@" --sample-scale 16)"
    local cmp rms p99 cost
    cmp=$("$FM" compare "$out/$tag.exr" "$out/$tag-16x.exr" --json)
    rms=$(echo "$cmp" | field rms)
    p99=$(echo "$cmp" | field p99)
    cost=$(awk -v s="$sec" -v r="$rms" 'BEGIN { print s * r * r }')
    [ -z "$clear_cost" ] && clear_cost=$cost
    printf '%-30s %-10s %-8s %9.2f %9.0f %9.3f %9.3f %12.2f %7.2f\n' "$name" "${WIDTH}x$((WIDTH / 2))" final "$sec" \
        "$mem" "$(awk -v x="$rms" 'BEGIN { print 100 * x }')" "$(awk -v x="$p99" 'BEGIN { print 100 * x }')" "$sec16" \
        "$(awk -v c="$cost" -v c0="$clear_cost" 'BEGIN { print c / c0 }')"
}

echo "firmament $("$FM" --version | cut -d' ' -f2), $(nproc) threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
printf '%-30s %-10s %-8s %9s %9s %9s %9s %12s %7s\n' sky size quality "wall s" "peak MiB" "RMS %" "p99 %" "16x wall s" "cost x"
bench_sky "clear (sun 30, no aerosol)" --sun-elevation 30 --biome none
bench_sky "default (sun 30, rural)" --sun-elevation 30 --biome rural
bench_sky "sunset (sun 2, urban, T 2)" --sun-elevation 2 --biome urban --turbidity 2
if [ "$BIOMES" = 1 ]; then
    for b in background desert-dust maritime-clean maritime-mineral polar-antarctic polar-arctic \
        remote-continental urban; do
        bench_sky "$b (sun 30)" --sun-elevation 30 --biome "$b"
    done
fi

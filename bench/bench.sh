#!/usr/bin/env bash
# The speed benchmark (docs/performance/: each finished run is added there).  For each sky it renders, with the sun disk left out
# (its aureole stays in) and all cores:
#   - a preview map 1024 x 512 and a final map 4096 x 2048 (and 1024 x 512 at final quality), timing
#     the whole `firmament render` run (wall s, peak MiB: /usr/bin/time; the median of three runs,
#     since the wall time of one varies by 10-20% from run to run on this machine);
#   - their error against the same sky rendered with 16 times the final quality's samples at the same
#     size (its own noise is about a quarter of the final map's, below 0.1% RMS by day): RMS and 99th
#     percentile of the relative luminance error over all pixels, from `firmament compare`.  That the
#     fast path has no bias beyond the reference mode's noise is a test
#     (tests/physics/test_fast_vs_reference.c);
#   - their error against the reference mode converged at 400 probe pixels of the 1024 x 512 map
#     (tests/data/bench_reference/SKY-1024.txt, cached, each file's header giving its paths per pixel
#     and RMS noise; a 4096 x 2048 map is averaged over 4 x 4 pixels there): "ref RMS %", the RMS
#     relative luminance error at the probes with the reference's own noise taken out in
#     quadrature, "ref bias %", its mean, and "ref p99 %", the 99th percentile of its magnitude over
#     the probes (the 4th largest of 400, as firmament compare takes it over a map's pixels; the
#     reference's noise left in).  Unlike the 16x map's, this error holds the fast path's bias too
#     (the fit's, the tables' interpolation);
#   - the speed-up against the reference mode at equal RMS error, measured in the same run: the
#     reference mode (per-pixel path tracing, no tables) renders 400 pixels of the 1024 x 512 map
#     with 256 paths each (bench/sky_bench.c); its time per pixel t and its RMS relative noise e
#     (from its own standard errors: it is unbiased) give the time it needs for the whole map at the
#     fast map's RMS error E against the converged reference, pixels x t x (e / E)^2, which is divided
#     by the fast map's wall time.
#
# With --biomes every error is the root mean square over three seeds' maps (three_seeds, below).
# "cost x" (with --biomes) is the wall time relative to the clear sky (no aerosol) at equal RMS
# error: Monte Carlo error falls as 1/sqrt(samples), so equal error costs wall * (RMS / RMS_clear)^2.
# "equal x" measures the same directly: the biome's wall time over the clear sky's at the sample
# scale (1 to 1/64, interpolated) where the clear sky's error is the biome's; the clear sky's fixed
# costs (tables, pixels, output) do not shrink with its paths, which the 1/sqrt law leaves out.
# "RMS % /4" and "equal /4" are the biome's error and "equal x" at a quarter of the final quality's
# paths (--sample-scale 0.25): the same question at an error about twice the final map's, where the
# fixed costs weigh more.
# "ref cost x" is the same ratio for the path tracer alone, without the fast path's tables and fit:
# the reference mode at 400 pixels of the map, 2048 paths each (bench/sky_bench.c: time per pixel
# x its RMS relative noise "ref RSD %" squared), which is what the sampling of the aerosols'
# scattering decides.
#   bench/bench.sh                  the default sky (sun 30, rural) and a sunset (sun 2, urban, T 2)
#   bench/bench.sh --biomes         1024 x 512 final maps of the clear sky and every biome at sun 30,
#                                   with their cost against the clear sky (issue "composition")
#   bench/bench.sh --twilight       one map's noise at sun -6, -12 and -18 (the default sky; and a
#                                   hazy one, urban at turbidity 2, at -18; final quality, 1024 x 512)
#                                   from two seeds' maps: the relative standard deviation of its
#                                   luminance, R / G and B / G and of its grain (from pixel to pixel),
#                                   the CIEDE2000 difference of the two maps as displayed at the
#                                   suggested exposure (mean, 99th percentile), and the flicker of a
#                                   time series (bench/seed_noise.h) (issue "Sun and sky geometry":
#                                   noise-free at -18)
#   bench/bench.sh --clouds         issue 48's speed target: the Overcast and Bright overcast noon
#                                   presets, stratus at sun 3 and -3, a fog around the observer (sun
#                                   30, 3 and -3 degrees) and the stratus seen from 3 km above the
#                                   ground (sun 30 and 3), the altostratus at sun -4, the High
#                                   cirrostratus preset and two layers at sun 10 as 4096 x 2048
#                                   final maps, wall and CPU time, memory and one map's noise from
#                                   two seeds (about 12 minutes on 2 cores today)
#   bench/bench.sh --live           the live sky (docs/rendering.md, "Live sky"; bench/live_bench.c):
#                                   per biome (none, rural, urban) the build time (wall and CPU: the
#                                   whole, then its two parts: the build a first map by day waits for,
#                                   and the twilight band a first sun below 1 degree adds), the
#                                   tables' memory, the time from a new sun to a written 512 x 256 map
#                                   (median of 40 suns; in half floats without the sun disk, as the
#                                   add-on's live maps, and in floats with it; wall and CPU, render and
#                                   write) and the process's peak memory; then the accuracy table: the
#                                   live map against the mean of two final quality seeds at the same
#                                   sun (128 x 64, no sun disk) at suns -18 to 90, luminance RMS, bias
#                                   and 99th percentile, mean and largest u'v' distance, that
#                                   reference's own noise and the RMS less it; below the horizon
#                                   (-18, -12, -6) again over three builds (the
#                                   product's and two with moved seeds: each build's RMS printed); the
#                                   product's build refined round by round (rural and urban: each
#                                   round's CPU seconds, and after it -18, -12 and -6 against the same
#                                   reference, as a server refines while idle); and
#                                   the zenith luminance swept in 0.1 degree
#                                   steps across the grid (the largest step across a grid elevation
#                                   against the largest elsewhere); and `firmament serve` as a client
#                                   sees it (bench/serve_latency.py, 512 x 256 maps of the default
#                                   sky): a request that builds the atmosphere (sun 30: all but the deep
#                                   twilight band), the next at -18 (the band built), a new server's first
#                                   with it on the disk, 40 suns with it in memory (median, 90th
#                                   percentile, largest; the server's atmosphere, render, write parts),
#                                   and the same 40 suns each sent into a round of refinement under way
#   bench/bench.sh --make-reference rewrites the converged references (after a change of the physics;
#                                   below 0.1% noise: about 15 minutes for the default sky and 3-4 hours
#                                   for the sunset on 2 cores)
#   bench/bench.sh --extend-reference SKY PATHS
#                                   adds a run of PATHS paths per probe, with a seed of its own, to
#                                   SKY's converged reference (pooled by the inverse square of each
#                                   one's noise; sky-bench merge prints how the run agrees with the
#                                   rest)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
# A run's figures (not the references' rewrites) are also kept in docs/performance/MODE.md
# (bench/record-run.sh), once the run has finished: the script runs itself through tee.
case "${1:-}" in
--make-reference | --extend-reference) ;;
*)
    if [ -z "${FM_BENCH_RECORDING:-}" ]; then
        log=$(mktemp)
        status=0
        FM_BENCH_RECORDING=1 "$0" "$@" | tee "$log" || status=$?
        mode=${1:---speed}
        [ "$status" -ne 0 ] || "$ROOT/bench/record-run.sh" "${mode#--}" "$log"
        rm -f "$log"
        exit "$status"
    fi
    ;;
esac
. "$ROOT/scripts/common.sh"
install_missing_packages
build build >/dev/null
cmake --build "$ROOT/build" --target sky-bench live-bench >/dev/null
FM="$ROOT/build/firmament"
SB="$ROOT/build/tools/sky-bench"
export FIRMAMENT_PRESETS="$ROOT/presets"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

field() { sed -n "s/.*\"$1\": \([0-9.eE+-]*\).*/\1/p" | tail -n 1; }

render() { # name, args... -> prints "wall_s peak_mib" of one run
    local name=$1
    shift
    /usr/bin/time -f '%e %M' -o "$out/$name.time" "$FM" render --no-sun-disk --progress none \
        -o "$out/$name.exr" "$@" >/dev/null
    awk '{ printf "%.2f %.0f\n", $1, $2 / 1024 }' "$out/$name.time"
}

timed() { # name, args... -> the median wall time of three runs (the same map each time) and the peak
    for run in 1 2 3; do render "$@"; done | sort -n | sed -n 2p
}

compare() { # a b -> prints "rms% p99%"
    local cmp
    cmp=$("$FM" compare "$out/$1.exr" "$out/$2.exr" --json)
    echo "$(echo "$cmp" | field rms) $(echo "$cmp" | field p99)" | awk '{ printf "%.3f %.3f\n", 100 * $1, 100 * $2 }'
}

# name, reference, args... -> "rms% p99%" of the map `name` (the default seed, rendered already) and
# of the same sky at seeds 2 and 3, each against the reference, as the root mean square over the
# three: one map's error moves by a fifth or more between seeds (desert dust 0.11-0.21%), which made
# the clear sky's curve below cross itself
three_seeds() {
    local name=$1 reference=$2
    shift 2
    for seed in 2 3; do render "$name-s$seed" "$@" --seed "$seed" >/dev/null; done
    for map in "$name" "$name-s2" "$name-s3"; do compare "$map" "$reference"; done |
        awk '{ r += $1 * $1; p += $2 * $2 } END { printf "%.3f %.3f\n", sqrt(r / NR), sqrt(p / NR) }'
}

row() { printf '%-28s %-10s %-8s %8s %9s %7s %7s %9s %10s %9s %12s\n' "$@"; }

REFERENCES="$ROOT/tests/data/bench_reference"
if [ "${1:-}" = "--make-reference" ]; then
    mkdir -p "$REFERENCES"
    for job in "default 600000" "sunset 12000000"; do
        read -r sky paths <<<"$job"
        "$SB" reference "$sky" 1024 "$paths" >"$out/$sky-1024.txt"
        mv "$out/$sky-1024.txt" "$REFERENCES/$sky-1024.txt"
        sed -n 2p "$REFERENCES/$sky-1024.txt"
    done
    exit 0
fi
if [ "${1:-}" = "--extend-reference" ]; then
    sky=${2:?--extend-reference SKY PATHS}
    paths=${3:?--extend-reference SKY PATHS}
    ref="$REFERENCES/$sky-1024.txt"
    # a seed no run of the file has taken: one past the largest
    seed=$(sed -n 's/^# run: [0-9]* paths, seed \([0-9]*\),.*/\1/p' "$ref" | sort -n | tail -n 1)
    "$SB" reference "$sky" 1024 "$paths" "$((seed + 1))" >"$out/run.txt"
    "$SB" merge "$sky" 1024 "$ref" "$out/run.txt" >"$out/merged.txt"
    mv "$out/merged.txt" "$ref"
    sed -n 2p "$ref"
    exit 0
fi

echo "firmament $("$FM" --version | cut -d' ' -f2), $(nproc) threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"

if [ "${1:-}" = "--biomes" ]; then
    # the clear sky's wall time against its error ("RMS % wall s" per line), for "equal x" (above)
    render none-16x --width 1024 --sun-elevation 30 --biome none --sample-scale 16 >/dev/null
    for scale in 1 0.5 0.25 0.125 0.0625 0.03125 0.015625; do
        read -r sec _ <<<"$(timed "none-$scale" --width 1024 --sun-elevation 30 --biome none --sample-scale "$scale")"
        read -r rms _ <<<"$(three_seeds "none-$scale" none-16x --width 1024 --sun-elevation 30 --biome none \
            --sample-scale "$scale")"
        echo "$rms $sec"
    done | sort -g >"$out/clear-curve.txt"
    echo "the clear sky's curve (RMS % : wall s):" $(awk '{ printf "%s:%s ", $1, $2 }' "$out/clear-curve.txt")
    # the clear sky's time at the error $1 (RMS %): log time linear in log error between the curve's
    # points; below its smallest error 1 / error^2 from there, above its largest the fastest time
    clear_time_at() {
        awk -v e="$1" 'NR == 1 { e0 = $1; t0 = $2 } { r[NR] = $1; t[NR] = $2 }
            END {
                if (e <= r[1]) { print t0 * (e0 / e) ^ 2; exit }
                for (i = 2; i <= NR; i++)
                    if (e <= r[i]) {
                        f = log(e / r[i - 1]) / log(r[i] / r[i - 1])
                        print exp(log(t[i - 1]) + f * log(t[i] / t[i - 1])); exit
                    }
                m = t[1]; for (i = 2; i <= NR; i++) if (t[i] < m) m = t[i]; print m
            }' "$out/clear-curve.txt"
    }
    printf '%-28s %-10s %8s %7s %7s %8s %8s %9s %12s %8s %8s\n' sky size "wall s" "RMS %" "p99 %" "cost x" "equal x" \
        "ref RSD %" "ref cost x" "RMS % /4" "equal /4"
    clear_cost=""
    clear_ref=""
    for b in none background desert-dust maritime-clean maritime-mineral polar-antarctic polar-arctic \
        remote-continental rural urban; do
        read -r sec _ <<<"$(timed "$b" --width 1024 --sun-elevation 30 --biome "$b")"
        [ -f "$out/$b-16x.exr" ] ||
            render "$b-16x" --width 1024 --sun-elevation 30 --biome "$b" --sample-scale 16 >/dev/null
        read -r rms p99 <<<"$(three_seeds "$b" "$b-16x" --width 1024 --sun-elevation 30 --biome "$b")"
        cost=$(awk -v s="$sec" -v r="$rms" 'BEGIN { print s * r * r }')
        [ -z "$clear_cost" ] && clear_cost=$cost
        # the path tracer alone (reference mode, 2048 paths at 400 pixels): time x noise^2
        read -r _ t_ref _ e_ref _ <<<"$("$SB" speed "biome:$b" 1024 2048)"
        ref=$(awk -v t="$t_ref" -v e="$e_ref" 'BEGIN { print t * e * e }')
        [ -z "$clear_ref" ] && clear_ref=$ref
        # the same at a quarter of the paths, an error nearer the preview's
        read -r sec4 _ <<<"$(timed "$b-q" --width 1024 --sun-elevation 30 --biome "$b" --sample-scale 0.25)"
        read -r rms4 _ <<<"$(three_seeds "$b-q" "$b-16x" --width 1024 --sun-elevation 30 --biome "$b" --sample-scale 0.25)"
        printf '%-28s %-10s %8.2f %7.3f %7.3f %8.2f %8.2f %9.3f %12.2f %8.3f %8.2f\n' "$b (sun 30)" 1024x512 "$sec" "$rms" \
            "$p99" "$(awk -v c="$cost" -v c0="$clear_cost" 'BEGIN { print c / c0 }')" \
            "$(awk -v s="$sec" -v c="$(clear_time_at "$rms")" 'BEGIN { print s / c }')" \
            "$(awk -v e="$e_ref" 'BEGIN { print 100 * e }')" "$(awk -v c="$ref" -v c0="$clear_ref" 'BEGIN { print c / c0 }')" \
            "$rms4" "$(awk -v s="$sec4" -v c="$(clear_time_at "$rms4")" 'BEGIN { print s / c }')"
    done
    exit 0
fi

if [ "${1:-}" = "--live" ]; then
    LB="$ROOT/build/tools/live-bench"
    # the final maps made once for every table below (the same seeds at the same suns)
    export LIVE_BENCH_FINAL_CACHE="$out/finals"
    mkdir -p "$LIVE_BENCH_FINAL_CACHE"
    for b in none rural urban; do "$LB" speed "$b" 40; done
    for b in none rural urban; do  # every sun against two final seeds: their own noise apart
        "$LB" accuracy "$b" 128 ref 2 -18 -12 -6 -2 0 2 5 10 20 30 45 60 90 | { [ "$b" = none ] && cat || tail -n +2; }
    done
    for b in none rural urban; do
        "$LB" accuracy "$b" 128 ref 2 seeds 3 -18 -12 -6 | { [ "$b" = none ] && cat || tail -n +2; }
    done
    for b in rural urban; do  # every round of refinement the library makes (64: more than it makes)
        "$LB" refine "$b" 128 ref 2 64 -18 -12 -6 | { [ "$b" = rural ] && cat || tail -n +2; }
    done
    for b in none urban; do "$LB" sweep "$b" -20 90 0.1 | tail -n 1; done
    python3 "$ROOT/bench/serve_latency.py" "$FM" --requests 40
    exit 0
fi

if [ "${1:-}" = "--clouds" ]; then
    # issue 48's target: an overcast (the Overcast preset: stratus, optical depth 30), the Bright overcast
    # noon preset (altostratus, optical depth 6, 3-4 km), the stratus deck at a sun of 3 degrees (below
    # the deck base's 5) and a fog with the observer inside it (0-200 m, visibility 200 m, optical depth
    # 3.9; the sun 30 degrees up and, a misty sunrise, 3 degrees), and the fog and the stratus at dusk
    # (sun -3: lit by the sky above them, docs/decisions/2026-12-07-twilight-fog.md), and the stratus seen
    # from above (a mountain top at 3 km, sun 30 and 3: docs/decisions/2026-12-07-above-deck.md), the
    # altostratus (3-4 km) at dusk (sun -4: docs/decisions/2026-12-07-deck-local-sun.md), the High
    # cirrostratus preset and cirrostratus over altostratus at sun 10 (docs/decisions/2026-12-07-thin-layers.md)
    # and 3 (docs/decisions/2026-12-07-two-layers-low-sun.md), the
    # Misty morning preset (shallow fog: 0-100 m, visibility 400 m, optical depth 1, sun 12.4;
    # docs/decisions/2026-12-07-shallow-fog.md), and cirrostratus (optical depth 1) at sunrise (sun 1: the
    # column) and at dusk (sun -3: the paths; docs/decisions/2026-12-07-thin-layers-twilight.md), and fog
    # (200 m, visibility 400 m) under cirrostratus at sun 10 (docs/decisions/2026-12-07-fog-under-thin-layers.md)
    # as 4096 x 2048 colour maps at
    # final quality: wall and CPU seconds (user + system; on a loaded machine compare CPU), peak memory,
    # and one map's noise: the RMS relative luminance difference of two seeds' maps over sqrt(2)
    printf '%-34s %-10s %7s %7s %9s %9s %6s\n' sky size "wall s" "CPU s" "peak MiB" "noise %" paths
    for job in "overcast --preset overcast" "bright-overcast-noon --preset bright-overcast-noon" \
        "stratus-low-sun --cloud stratus --sun-elevation 3" "fog --fog-visibility 200 --sun-elevation 30" \
        "fog-low-sun --fog-visibility 200 --sun-elevation 3" "fog-dusk --fog-visibility 200 --sun-elevation -3" \
        "stratus-dusk --cloud stratus --sun-elevation -3" "above-overcast --cloud stratus --altitude 3000" \
        "above-overcast-low-sun --cloud stratus --altitude 3000 --sun-elevation 3" \
        "altostratus-dusk --cloud altostratus --sun-elevation -4" \
        "high-cirrostratus --preset high-cirrostratus" "two-layers --cloud cirrostratus,altostratus --sun-elevation 10" \
        "two-layers-low-sun --cloud cirrostratus,altostratus --sun-elevation 3" \
        "fog-under-cirrostratus --cloud cirrostratus --fog-visibility 400 --sun-elevation 10" \
        "misty-morning --preset misty-morning" \
        "cirrostratus-sunrise --cloud cirrostratus --sun-elevation 1" \
        "cirrostratus-dusk --cloud cirrostratus --sun-elevation -3"; do
        read -r name extra <<<"$job"
        read -r -a extra <<<"$extra"
        for seed in 1 2; do
            /usr/bin/time -f '%e %U %S %M' -o "$out/$name-$seed.time" "$FM" render --no-sun-disk --progress none \
                -o "$out/$name-$seed.exr" --width 4096 --quality final --seed "$seed" "${extra[@]}" >/dev/null
        done
        noise=$("$FM" compare "$out/$name-1.exr" "$out/$name-2.exr" --json | field rms |
            awk '{ printf "%.3f", 100 * $1 / sqrt(2) }')
        paths=$(sed -n 's/.*"paths_per_node":[[:space:]]*\([0-9]*\).*/\1/p' "$out/$name-1.json" | head -n 1)
        read -r wall user sys kib <"$out/$name-1.time"
        printf '%-34s %-10s %7.1f %7.1f %9.0f %9s %6s\n' "$name (${extra[*]})" 4096x2048 "$wall" \
            "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" "$(awk -v k="$kib" 'BEGIN { print k / 1024 }')" \
            "$noise" "$paths"
    done
    exit 0
fi

if [ "${1:-}" = "--twilight" ]; then
    # final quality, 1024 x 512, seeds 1 and 2 (sky-bench seeds: one map's noise), and each seed's next
    # frame of a time series 0.25 degrees on (a minute or two; sky-bench flicker): the default sky at
    # sun -6, -12 and -18, and a hazy one (urban, turbidity 2) at -18
    json() { sed -n "s/.*\"$2\":[[:space:]]*\([0-9.eE+-]*\).*/\1/p" "$out/$1.json" | head -n 1; }
    pct() { awk -v v="$1" 'BEGIN { print 100 * v }'; }
    printf '%-22s %7s %6s %8s %7s %7s %8s %8s %7s %10s\n' sky "wall s" paths "Y %" "R/G %" "B/G %" "grain %" \
        "dE mean" "dE p99" "flicker %"
    for job in "rural -6" "rural -12" "rural -18" "urban -18 --biome urban --turbidity 2"; do
        read -r biome sun extra <<<"$job"
        read -r -a extra <<<"$extra"
        next=$(awk -v s="$sun" 'BEGIN { print s + 0.25 }')
        a="tw-$biome$sun" b="tw-$biome$next"
        for seed in 1 2; do
            render "$a-$seed" --width 1024 --sun-elevation "$sun" --seed "$seed" "${extra[@]}" >"$out/$a-$seed.wall"
            render "$b-$seed" --width 1024 --sun-elevation "$next" --seed "$seed" "${extra[@]}" >/dev/null
        done
        ev=$(json "$a-1" suggested_exposure_ev)
        read -r _ y _ rg _ bg _ grain _ de _ de99 <<<"$("$SB" seeds "$out/$a-1.exr" "$out/$a-2.exr" "$ev")"
        read -r _ fl <<<"$("$SB" flicker "$out/$a-1.exr" "$out/$b-1.exr" "$out/$a-2.exr" "$out/$b-2.exr")"
        label="$biome${extra[*]:+ T ${extra[3]}} (sun $sun)"
        printf '%-22s %7.2f %6s %8.2f %7.2f %7.2f %8.3f %8.2f %7.2f %10.2f\n' "$label" \
            "$(cat "$out/$a-1.wall" "$out/$a-2.wall" | awk '{ s += $1 } END { print s / NR }')" \
            "$(json "$a-1" paths_per_node)" "$(pct "$y")" "$(pct "$rg")" "$(pct "$bg")" "$(pct "$grain")" "$de" "$de99" \
            "$(pct "$fl")"
    done
    exit 0
fi

row sky size quality "wall s" "peak MiB" "RMS %" "p99 %" "ref RMS %" "ref bias %" "ref p99 %" "vs reference"
for sky in default sunset; do
    read -r -a args <<<"$("$SB" args "$sky")"
    label="$sky ($(echo "${args[*]}" | sed 's/--sun-elevation \([0-9-]*\).*--biome \([a-z-]*\) --turbidity \([0-9.]*\)/sun \1, \2, T \3/'))"
    # the reference mode's time per pixel and noise at 256 paths (400 pixels of the 1024 x 512 map)
    read -r _ t_ref _ e_ref _ <<<"$("$SB" speed "$sky" 1024 256)"
    for job in "1024 preview" "1024 final" "4096 final"; do
        read -r width quality <<<"$job"
        name="$sky-$width-$quality"
        [ -f "$out/$sky-$width-16x.exr" ] ||
            render "$sky-$width-16x" "${args[@]}" --width "$width" --sample-scale 16 >/dev/null
        read -r sec mib <<<"$(timed "$name" "${args[@]}" --width "$width" --quality "$quality")"
        read -r rms p99 <<<"$(compare "$name" "$sky-$width-16x")"
        # against the converged reference at its probes: error without the reference's noise, bias
        read -r _ _ _ _ _ ref_rms _ ref_bias _ _ _ ref_p99 \
            <<<"$("$SB" error "$out/$name.exr" "$REFERENCES/$sky-1024.txt")"
        read -r ref_rms ref_bias ref_p99 <<<"$(awk -v r="$ref_rms" -v b="$ref_bias" -v p="$ref_p99" \
            'BEGIN { printf "%.3f %+.3f %.3f", 100 * r, 100 * b, 100 * p }')"
        speedup=$(awk -v t="$t_ref" -v e="$e_ref" -v E="$ref_rms" -v w="$width" -v s="$sec" \
            'BEGIN { printf "%.0fx", w * w / 2 * t * (100 * e / E) ^ 2 / s }')
        row "$label" "${width}x$((width / 2))" "$quality" "$sec" "$mib" "$rms" "$p99" "$ref_rms" "$ref_bias" \
            "$ref_p99" "$speedup"
    done
done

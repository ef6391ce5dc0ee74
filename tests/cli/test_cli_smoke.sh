#!/usr/bin/env bash
# Every path of the executable once, on tiny maps with few samples: for the sanitizer build
# (AddressSanitizer + UndefinedBehaviorSanitizer, scripts/test), where the full CLI tests
# (test_cli.sh, test_cli_presets.sh: their values, messages and files, in the plain build) would take
# many minutes.  Here each run must succeed and write what it names, or be refused with exit 2
# and one line; the sanitizers watch the memory and the arithmetic of all of it.
# Usage: test_cli_smoke.sh path/to/firmament
set -u
FM=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
. "$here/harness.sh"
mkdir -p "$work/out"
o=$work/out
quick=(--quality preview --sample-scale 0.05 --progress none)

runs() { # description, args...: exit 0
    local what=$1
    shift
    if "$FM" "$@" >"$work/stdout" 2>"$work/stderr"; then ok; else fail "$what: exit $?: $(cat "$work/stderr")"; fi
}
written() { for f in "$@"; do [ -s "$f" ] && ok || fail "$f not written"; done; }

runs "help" --help
runs "version" --version
runs "render help" render --help
runs "equirect" render --width 16 "${quick[@]}" -o "$o/eq.exr" --preview "$o/eq.png"
written "$o/eq.exr" "$o/eq.json" "$o/eq.png"
runs "radiance" render --width 16 "${quick[@]}" -o "$o/eq.hdr"
written "$o/eq.hdr"
# batch: plan (a product and a weather file), run, rerun, summary, a Slurm script
runs "batch plan" batch plan -o "$o/m.jsonl" --out-dir b --preset clear-noon --place p,48.9,2.35,+01:00 \
    --date 2025-06-21 --times 09:00,12:00 --sun-above 0 --set width=16 --set quality=preview --set sample_scale=0.05
runs "batch plan --epw" batch plan -o "$o/e.jsonl" --epw "$root/tests/data/epw/synthetic.epw" --set width=16
runs "batch run" batch run "$o/m.jsonl" --index 0 --count 2 --threads 1
runs "batch rerun" batch run "$o/m.jsonl" --index 1 --skip-existing
runs "batch summary" batch summary "$o/m.jsonl"
runs "batch slurm" batch slurm "$o/m.jsonl" --jobs-per-task 2
written "$o/b/clear-noon_p_20250621_1200.exr" "$o/m.csv" "$o/m.png" "$o/m.sbatch"
runs "fisheye" render --width 16 --camera fisheye --fisheye-projection equisolid "${quick[@]}" -o "$o/fish.exr"
runs "pinhole" render --width 16 --camera pinhole --fov 40 --aspect 4:3 "${quick[@]}" -o "$o/pin.exr"
runs "reference" render --width 8 --quality reference --samples 4 --progress none -o "$o/ref.exr"
runs "reference pinhole" render --width 16 --aspect 2 --camera pinhole --quality reference --samples 4 --progress none \
    -o "$o/refpin.exr"
runs "twilight" render --width 16 --sun-elevation -6 "${quick[@]}" -o "$o/twi.exr"
runs "aerosols, humidity, hg phase" render --width 16 --biome desert-dust --humidity 70 --aerosol-phase hg \
    --turbidity 2 "${quick[@]}" -o "$o/dust.exr"
runs "aod550" render --width 16 --biome urban --aod550 0.4 "${quick[@]}" -o "$o/urban.exr"
runs "date, time, place" render --width 16 --date 2024-06-21 --time 18:30 --utc-offset +02:00 --latitude 48.85 \
    --longitude 2.35 --altitude 3000 "${quick[@]}" -o "$o/paris.exr"
runs "time series" render --width 8 --date 2024-06-21 --time-start 12:00 --time-end 12:30 --step 30 --latitude 40 --longitude 0 \
    "${quick[@]}" -o "$o/series.exr"
written "$o/series_0000.exr" "$o/series_0001.exr"
runs "wavelength" render --width 16 --wavelength 550 "${quick[@]}" -o "$o/mono.exr"
runs "custom atmosphere" render --width 16 --atmosphere "$root/presets/atmospheres/reference-rayleigh-aerosol-albedo.json" \
    --wavelength 440 "${quick[@]}" -o "$o/atm.exr"
runs "spectral, ACEScg, half, piz" render --width 16 --no-sun-disk --spectral "$o/spec.exr" --colorspace ACEScg --half \
    --compression piz "${quick[@]}" -o "$o/aces.exr"
written "$o/spec.exr"
runs "dwaa" render --width 16 --no-sun-disk --compression dwaa "${quick[@]}" -o "$o/dwaa.exr"
runs "preset and sun-disk map" render --preset golden-hour --width 16 "${quick[@]}" --sun-disk-map "$o/disk.exr" \
    -o "$o/preset.exr"
written "$o/disk.exr" "$o/disk.json"
runs "progress json" render --width 8 --quality preview --sample-scale 0.05 --progress json -o "$o/p.exr"
grep -q '"event": "done"' "$work/stdout" && ok || fail "progress json: no done event"
runs "sun" sun --date 2024-06-21 --time 12:00 --latitude 70 --longitude 20 --json
runs "polar night" sun --date 2024-12-21 --time 12:00 --latitude 80 --longitude 0
runs "compare" compare "$o/eq.exr" "$o/eq.exr" --exclude-sun 2 --json
runs "info" info "$o/aces.exr"
runs "list colour spaces" render --list-colorspaces

# serve: a bad line and a map, then the end of the input; a second server takes the atmosphere from
# the disk cache (tests/cli/test_serve.py checks the protocol)
printf '%s\n' 'not json' "{\"id\": 1, \"output\": \"$o/served.exr\", \"width\": 16, \"quality\": \"preview\"}" \
    >"$work/requests"
runs "serve" serve --cache "$work/cache" <"$work/requests"
written "$o/served.exr" "$o/served.json"
grep -q '"status":"error"' "$work/stdout" && grep -q '"cache":"built"' "$work/stdout" && ok ||
    fail "serve: $(cat "$work/stdout")"
runs "serve, disk cache" serve --cache "$work/cache" <"$work/requests"
grep -q '"cache":"disk"' "$work/stdout" && ok || fail "serve, disk cache: $(cat "$work/stdout")"

mkdir -p "$work/bad" && printf '{"sun_elevation": 30,' >"$work/bad/broken.json"
expect_usage_error "malformed preset" render --preset "$work/bad/broken.json" --width 16
expect_usage_error "malformed atmosphere" render --atmosphere "$work/bad/broken.json" --wavelength 550
expect_usage_error "unknown biome" render --biome fog
expect_usage_error "bad date" render --date 2023-02-30 --latitude 10
expect_usage_error "odd width" render --width 15
expect_usage_error "unreadable EXR" info "$work/bad/broken.json"

# Ctrl-C during the tables: nothing left behind
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 64 --progress none -o "$work/out/sky.exr" &
pid=$!
sleep 1
kill -INT $pid
wait $pid
rc=$?
[ $rc -eq 130 ] && ok || fail "SIGINT: exit $rc, expected 130"
[ -z "$(ls -A "$work/out")" ] && ok || fail "SIGINT left files: $(ls -A "$work/out")"

echo "$checks checks passed, $failures failed"
[ $failures -eq 0 ]

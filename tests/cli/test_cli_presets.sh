#!/usr/bin/env bash
# Sky presets (render --preset), the disk in a second map (--sun-disk-map) and the sidecar's
# suggested exposure; a test of its own beside test_cli.sh (every shipped preset is rendered).
# Usage: test_cli_presets.sh path/to/firmament
set -u
FM=$(realpath "$1") # absolute: the cases run from their own directories
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
. "$here/harness.sh"

# --- sky presets (presets/skies, render --preset) ------------------------------------------------
json_get() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval('d' + sys.argv[2]))" "$@"; }
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --preset golden-hour --width 16 --quality preview --progress none -o "$work/out/g.exr" && ok ||
    fail "--preset golden-hour"
# the preset's place and time put the sun where `firmament sun` does (Paris, 2024-06-21 21:15 CEST)
el=$("$FM" sun --date 2024-06-21 --time 21:15 --utc-offset +02:00 --latitude 48.8566 --longitude 2.3522 --json |
    python3 -c "import json,sys; print(json.load(sys.stdin)['elevation_deg'])")
python3 -c "import sys; sys.exit(abs($(json_get "$work/out/g.json" "['sun']['elevation_deg']") - $el) > 1e-5)" && ok ||
    fail "golden-hour sun elevation $(json_get "$work/out/g.json" "['sun']['elevation_deg']") != $el"
[ "$(json_get "$work/out/g.json" "['parameters']['biome']")" = rural ] && ok || fail "golden-hour biome"
# explicit options override the preset: the sun's angles, the turbidity (by aod550), the albedo
"$FM" render --preset hazy-desert --sun-elevation 50 --sun-azimuth 10 --turbidity 2 --albedo 0.5 --width 16 \
    --quality preview --progress none -o "$work/out/h.exr" && ok || fail "--preset with overrides"
[ "$(json_get "$work/out/h.json" "['sun']['elevation_deg']")" = 50 ] && ok || fail "override --sun-elevation"
[ "$(json_get "$work/out/h.json" "['parameters']['turbidity']")" = 2 ] && ok || fail "override --turbidity over aod550"
[ "$(json_get "$work/out/h.json" "['parameters']['ground_albedo']")" = 0.5 ] && ok || fail "override --albedo"
[ "$(json_get "$work/out/h.json" "['parameters']['biome']")" = desert-dust ] && ok || fail "preset biome kept"
# every shipped preset renders (a preset file is also accepted by path)
for p in "$here"/../../presets/skies/*.json; do
    "$FM" render --preset "$(realpath "$p")" --width 8 --quality preview --progress none -o "$work/out/p.exr" && ok ||
        fail "shipped preset $p"
done
expect_usage_error "unknown preset" render --preset nowhere
grep -q 'known: blue-hour, bright-overcast-noon, clear-noon, golden-hour' "$work/stderr" && ok || fail "unknown preset lists names: $(cat "$work/stderr")"
expect_usage_error "--preset twice" render --preset clear-noon --preset golden-hour
bad() { # bad "what" 'json text' 'expected message part'
    printf '%s' "$2" >"$work/bad.json"
    expect_usage_error "malformed preset: $1" render --preset "$work/bad.json"
    grep -qF -- "$3" "$work/stderr" && grep -qF -- "bad.json" "$work/stderr" && ok ||
        fail "malformed preset $1: $(cat "$work/stderr")"
}
bad "syntax" '{"name": "x", "turbidity": 1,}' 'bad.json:1:'
bad "no name" '{"turbidity": 1}' '$'
bad "unknown key" '{"name": "x", "turbidty": 1}' 'turbidty'
bad "wrong type" '{"name": "x", "turbidity": "high"}' '$.turbidity'
bad "out of range" '{"name": "x", "albedo": 1.5}' '$.albedo'
bad "both aerosol amounts" '{"name": "x", "turbidity": 1, "aod550": 0.2}' '$.aod550'
bad "bad date" '{"name": "x", "date": "2024-13-01", "latitude": 10}' '$.date'
bad "bad time" '{"name": "x", "date": "2024-01-01", "time": "25:00", "latitude": 10}' '--time'
expect_usage_error "--preset without value" render --preset
# values refused after parsing (by the renderer, the biome loader) name the preset file too, unless
# the user gave that option
bad "odd width" '{"name": "x", "width": 63}' '--width: 63'
bad "unknown biome" '{"name": "x", "biome": "jungle"}' '--biome: unknown biome'
printf '{"name": "x", "width": 63}' >"$work/bad.json"
expect_usage_error "odd width given by the user" render --preset "$work/bad.json" --width 65
grep -q '^firmament: --width: 65' "$work/stderr" && ok || fail "the user's own value: $(cat "$work/stderr")"
bad "camera key of the wrong type" '{"name": "x", "fov": "wide"}' '$.fov'
bad "fov out of range" '{"name": "x", "camera": "pinhole", "fov": 200}' '$.fov'
bad "unknown camera" '{"name": "x", "camera": "periscope"}' '--camera'

# --- a job with a view: the thesis figures of scenes/thesis/ -------------------------------------
rm -rf "$work/out" && mkdir -p "$work/out"
for f in "$ROOT"/scenes/thesis/*.json; do
    "$FM" render --preset "$f" --quality preview --sample-scale 0.05 --width 32 --progress none -o "$work/out/j.exr" ||
        fail "thesis job $(basename "$f")"
done && ok
"$FM" render --preset "$ROOT/scenes/thesis/pinhole-january-sun-0.json" --quality preview --sample-scale 0.05 \
    --progress none -o "$work/out/pin.exr" && python3 -c "
import json, sys
d = json.load(open('$work/out/pin.json'))
c, i = d['camera'], d['image']
sys.exit(not (c['type'] == 'pinhole' and c['horizontal_fov_deg'] == 90 and c['look_azimuth_deg'] == 240 and
              i['width'] == 384 and i['height'] == 216))" && ok || fail "the preset's view: pinhole 90 deg, 384 x 216"
# another camera on the command line replaces the preset's whole view (no stray --fov)
"$FM" render --preset "$ROOT/scenes/thesis/pinhole-january-sun-0.json" --camera equirect --width 32 --quality preview \
    --sample-scale 0.05 --progress none -o "$work/out/eq.exr" &&
    [ "$(json_get "$work/out/eq.json" "['camera']['type']")" = equirect ] && ok || fail "--camera replaces the preset's view"

# --- the sun disk in a second map (--sun-disk-map) and the suggested exposure --------------------
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 64 --quality preview --progress none -o "$work/out/sky.exr" --sun-disk-map "$work/out/disk.exr" &&
    "$FM" render --width 64 --quality preview --progress none -o "$work/out/full.exr" &&
    "$FM" render --width 64 --quality preview --progress none --no-sun-disk -o "$work/out/bare.exr" && ok ||
    fail "--sun-disk-map render"
[ "$(json_get "$work/out/sky.json" "['image']['contains_sun_disk']")" = False ] && ok || fail "main map holds no disk"
[ "$(json_get "$work/out/disk.json" "['image']['contains_sun_disk']")" = True ] && ok || fail "disk map holds the disk"
# same bits as the separate renders with and without the disk
"$FM" compare "$work/out/disk.exr" "$work/out/full.exr" --json | grep -q '"max": 0,' && ok || fail "disk map = full render"
# (sky + disk) - disk: float rounding only (away from the disk, where it cancels ~1e3 times the sky)
"$FM" compare "$work/out/sky.exr" "$work/out/bare.exr" --exclude-sun 1 --json |
    python3 -c "import json,sys; sys.exit(json.load(sys.stdin)['max'] > 1e-4)" && ok || fail "main map = --no-sun-disk render"
# EV = log2(683 pi / E_global), within LO..HI: 100 klx -> -5.54
ev_matches() { # sidecar, lo, hi
    python3 -c "
import json, math, sys
d = json.load(open('$1'))['sky']
ev = math.log2(683 * math.pi / d['global_horizontal_illuminance_lux'])
sys.exit(abs(d['suggested_exposure_ev'] - ev) > 1e-9 or not $2 < ev < $3)"
}
ev_matches "$work/out/sky.json" -6.5 -4 && ok || fail "suggested_exposure_ev"
# deep twilight needs more than +20 EV (sun -16: about 2e-4 lx, +23.4); Blender's film exposure
# reaches +32, so the suggestion is not cut short below that
"$FM" render --quality preview --width 64 --sun-elevation -16 --progress none -o "$work/out/dusk.exr" >/dev/null
ev_matches "$work/out/dusk.json" 22 25 && ok || fail "suggested_exposure_ev at sun -16"
expect_usage_error "--sun-disk-map with --no-sun-disk" render --no-sun-disk --sun-disk-map d.exr

echo "$checks checks passed, $failures failed"
[ $failures -eq 0 ]

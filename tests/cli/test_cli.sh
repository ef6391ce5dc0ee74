#!/usr/bin/env bash
# The firmament executable's behaviour: exit codes, one-line messages naming the problem, outputs
# written completely or not at all (errors, SIGINT, SIGTERM), progress lines, `compare`.
# Usage: test_cli.sh path/to/firmament
set -u
FM=$(realpath "$1") # absolute: the cases run from their own directories
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
checks=0

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { checks=$((checks + 1)); }

# no file of any kind left in $work/out (a clean directory per case)
expect_empty_dir() {
    local left
    left=$(ls -A "$work/out")
    if [ -n "$left" ]; then fail "$1: files left behind: $left"; else ok; fi
}

# expect_usage_error "description" args...: exit 2, exactly one stderr line starting "firmament:"
expect_usage_error() {
    local what=$1
    shift
    rm -rf "$work/out" && mkdir -p "$work/out"
    (cd "$work/out" && "$FM" "$@" >"$work/stdout" 2>"$work/stderr")
    local rc=$?
    local lines
    lines=$(wc -l <"$work/stderr")
    if [ $rc -ne 2 ]; then fail "$what: exit $rc, expected 2"; else ok; fi
    if [ "$lines" -ne 1 ] || ! grep -q '^firmament: ' "$work/stderr"; then
        fail "$what: expected one 'firmament:' line on stderr, got: $(cat "$work/stderr")"
    else ok; fi
    expect_empty_dir "$what"
}

# --- help and version -------------------------------------------------------------------------
"$FM" --help >"$work/help" 2>&1 && grep -q -- '--sun-elevation' "$work/help" && ok || fail "--help"
"$FM" render --help >"$work/help" 2>&1 && grep -q -- '--wavelength' "$work/help" && ok || fail "render --help"
"$FM" --version | grep -Eq '^firmament [0-9]+\.[0-9]+\.[0-9]+$' && ok || fail "--version"

# --- bad input: exit 2, one line, nothing written ----------------------------------------------
expect_usage_error "no command"
expect_usage_error "unknown command" fly
expect_usage_error "elevation above 90" render --sun-elevation 95
expect_usage_error "elevation below -90" render --sun-elevation -90.5
expect_usage_error "elevation not a number" render --sun-elevation high
expect_usage_error "azimuth out of range" render --sun-azimuth 400
expect_usage_error "negative albedo" render --albedo -0.1
expect_usage_error "albedo above 1" render --albedo 1.5
expect_usage_error "negative altitude" render --altitude -3
expect_usage_error "altitude above 20 km" render --altitude 30000
expect_usage_error "negative ozone" render --ozone-du -1
expect_usage_error "unknown biome" render --biome jungle
grep -q 'known: none, background, desert-dust' "$work/stderr" && ok || fail "unknown biome lists the names: $(cat "$work/stderr")"
expect_usage_error "negative turbidity" render --turbidity -0.5
grep -q -- '--turbidity' "$work/stderr" && ok || fail "turbidity message names the flag"
expect_usage_error "absurd turbidity" render --turbidity 1e6
expect_usage_error "negative aod550" render --aod550 -0.1
expect_usage_error "humidity above 99" render --humidity 100
expect_usage_error "unknown aerosol phase" render --aerosol-phase rayleigh
expect_usage_error "missing biome file" render --biome /nonexistent/biome.json
expect_usage_error "invalid date" render --date 2023-02-30 --latitude 45
grep -q -- '--date' "$work/stderr" && ok || fail "date message names the flag"
expect_usage_error "malformed date" render --date 2023-2-3 --latitude 45
expect_usage_error "date without a place" render --date 2023-06-01
expect_usage_error "latitude beyond 90" render --date 2023-06-01 --latitude 91
mkdir -p "$work/biomes"
printf '{"name": "x", "humidity_percent": 50, "layers": [\n  {"name": "bl", "bottom_km": 0, "top_km": 2,\n' >"$work/biomes/truncated.json"
expect_usage_error "biome file with a syntax error" render --biome "$work/biomes/truncated.json"
grep -q 'truncated.json:3:1: JSON syntax error: unexpected end of file' "$work/stderr" && ok || fail "syntax error position: $(cat "$work/stderr")"
printf '{"name": "x", "humidity_percent": 50, "layers": [{"name": "bl", "bottom_km": 0, "top_km": 2, "number_density_cm3": {"wasso": 10}}]}\n' >"$work/biomes/typo.json"
expect_usage_error "biome file with an unknown component" render --biome "$work/biomes/typo.json"
grep -q 'typo.json: \$.layers\[0\].number_density_cm3: unknown OPAC component "wasso"' "$work/stderr" && ok || fail "JSON path in the message: $(cat "$work/stderr")"
printf '{"name": "x", "humidity_percent": 50, "layers": [{"name": "bl", "bottom_km": 3, "top_km": 2, "number_density_cm3": {"waso": 10}}]}\n' >"$work/biomes/upside.json"
expect_usage_error "biome layer upside down" render --biome "$work/biomes/upside.json"
expect_usage_error "biome with a custom atmosphere" render --atmosphere "$(dirname "$0")/../../presets/atmospheres/reference-rayleigh.json" --biome urban
grep -q -- '--biome: does not apply with --atmosphere' "$work/stderr" && ok || fail "conflict message: $(cat "$work/stderr")"
expect_usage_error "width 0" render --width 0
expect_usage_error "absurd width" render --width 1000000
expect_usage_error "odd width" render --width 1001
expect_usage_error "width not an integer" render --width 12.5
expect_usage_error "wavelength below range" render --wavelength 200
expect_usage_error "unknown quality" render --quality ultra
expect_usage_error "unknown progress mode" render --progress loud
expect_usage_error "negative seed" render --seed -1
expect_usage_error "threads out of range" render --threads 1000
expect_usage_error "samples zero" render --samples 0
expect_usage_error "nan" render --albedo nan
expect_usage_error "unknown option" render --turbo
expect_usage_error "missing value" render --width
expect_usage_error "stray argument" render sky.exr
expect_usage_error "output directory missing" render --width 16 -o "$work/no/such/dir/sky.exr"
expect_usage_error "output inside a file" render --width 16 -o /dev/null/sky.exr
expect_usage_error "output is a directory" render --width 16 -o "$work"

# the message names the option
rm -rf "$work/out" && mkdir -p "$work/out"
(cd "$work/out" && "$FM" render --sun-elevation 95 2>"$work/stderr")
grep -q -- '--sun-elevation' "$work/stderr" && grep -q '95' "$work/stderr" && ok || fail "message names the option: $(cat "$work/stderr")"

# --- custom atmospheres (--atmosphere FILE) ----------------------------------------------------
presets=$(cd "$(dirname "$0")/../../presets/atmospheres" && pwd)
grep -q -- '--atmosphere' "$work/help" && ok || fail "render --help mentions --atmosphere"
printf '{\n  "planet_radius_km": 6360,\n  "top_altitude_km": 60,,\n}\n' >"$work/bad-syntax.json"
printf '{"planet_radius_km": 6360, "top_altitude_km": 60, "constituents": [{"profile": {"type": "exponential", "scale_height_km": 8}, "scattering": 1e-5, "phase": {"type": "henyey-greenstein", "g": 1.5}}]}\n' >"$work/bad-g.json"
expect_usage_error "atmosphere file with a syntax error" render --atmosphere "$work/bad-syntax.json" --wavelength 550
expect_usage_error "atmosphere file with g out of range" render --atmosphere "$work/bad-g.json" --wavelength 550
expect_usage_error "missing atmosphere file" render --atmosphere "$work/no-such-atmosphere.json"
expect_usage_error "atmosphere file without the colour wavelengths" render --atmosphere "$presets/reference-rayleigh.json"
# the messages name the flag, the file, and where and what the problem is
rm -rf "$work/out" && mkdir -p "$work/out"
(cd "$work/out" && "$FM" render --atmosphere "$work/bad-syntax.json" --wavelength 550 2>"$work/stderr")
grep -q -- "--atmosphere: $work/bad-syntax.json:3:25: JSON syntax error" "$work/stderr" && ok || fail "syntax error message: $(cat "$work/stderr")"
(cd "$work/out" && "$FM" render --atmosphere "$work/bad-g.json" --wavelength 550 2>"$work/stderr")
grep -qF -- "--atmosphere: $work/bad-g.json: \$.constituents[0].phase.g: must be in (-1, 1), not 1.5" "$work/stderr" && ok ||
    fail "range error message: $(cat "$work/stderr")"
(cd "$work/out" && "$FM" render --atmosphere "$presets/reference-rayleigh.json" 2>"$work/stderr")
grep -q 'given for 440-680 nm (constituent "molecules"), but the render needs 380-780 nm' "$work/stderr" && ok ||
    fail "wavelength coverage message: $(cat "$work/stderr")"
# the four reference atmospheres render at 550 nm
for f in reference-rayleigh reference-rayleigh-ozone reference-rayleigh-aerosol reference-rayleigh-aerosol-albedo; do
    rm -rf "$work/out" && mkdir -p "$work/out"
    if "$FM" render --atmosphere "$presets/$f.json" --wavelength 550 --width 16 --quality preview --progress none \
        -o "$work/out/$f.exr" 2>"$work/stderr" && [ -s "$work/out/$f.exr" ] && [ -s "$work/out/$f.json" ]; then ok; else
        fail "render $f at 550 nm: $(cat "$work/stderr")"
    fi
done
grep -q '"custom"' "$work/out/reference-rayleigh-aerosol-albedo.json" && ok || fail "sidecar reports a custom atmosphere"

# --- a successful render -----------------------------------------------------------------------
rm -rf "$work/out" && mkdir -p "$work/out"
if "$FM" render --width 32 --quality preview --progress none -o "$work/out/sky.exr"; then ok; else fail "small render"; fi
[ -s "$work/out/sky.exr" ] && [ -s "$work/out/sky.json" ] && ok || fail "render wrote sky.exr and sky.json"
[ "$(ls -A "$work/out" | wc -l)" -eq 2 ] && ok || fail "no temporary file left: $(ls -A "$work/out")"
[ "$(head -c 4 "$work/out/sky.exr" | od -An -tx1 | tr -d ' ')" = "762f3101" ] && ok || fail "EXR magic number"
grep -q '"direct_normal_irradiance_rgb"' "$work/out/sky.json" && grep -q '"diffuse_horizontal_illuminance_lux"' "$work/out/sky.json" && ok || fail "sidecar keys"
# a custom sidecar path, and a name without an extension
"$FM" render --width 16 --quality preview -o "$work/out/noext" --sidecar "$work/out/meta.json" && [ -s "$work/out/noext" ] && [ -s "$work/out/meta.json" ] && ok || fail "--sidecar"
"$FM" render --width 16 --quality preview -o "$work/out/plain" && [ -s "$work/out/plain.json" ] && ok || fail "default sidecar without extension"

# JSON progress: one object per line on stdout, ending with "done"
"$FM" render --width 32 --quality preview --progress json -o "$work/out/p.exr" >"$work/progress" 2>"$work/stderr"
grep -q '"event": "progress"' "$work/progress" && tail -n 1 "$work/progress" | grep -q '"event": "done"' && ok || fail "json progress: $(tail -n 2 "$work/progress")"
[ ! -s "$work/stderr" ] && ok || fail "json progress writes nothing to stderr"

# --- compare ------------------------------------------------------------------------------------
"$FM" compare "$work/out/sky.exr" "$work/out/sky.exr" --exclude-sun 2 --json | grep -q '"rms": 0,' && ok || fail "compare identical maps"
"$FM" compare "$work/out/sky.exr" "$work/out/noext" >/dev/null 2>"$work/stderr"
[ $? -eq 2 ] && grep -q 'differ in size' "$work/stderr" && ok || fail "compare different sizes"

# --- cameras ------------------------------------------------------------------------------------
grep -q -- '--camera TYPE' "$work/help" && grep -q -- '--look-elevation' "$work/help" && ok || fail "render --help lists the camera options"
expect_usage_error "unknown camera" render --camera spherical
grep -q -- "--camera: 'spherical' is not one of equirect, fisheye, pinhole" "$work/stderr" && ok || fail "camera message: $(cat "$work/stderr")"
expect_usage_error "unknown fisheye projection" render --camera fisheye --fisheye-projection stereographic
expect_usage_error "fov of 0" render --camera pinhole --fov 0
expect_usage_error "fov beyond 170" render --camera pinhole --fov 171
grep -q -- '--fov: 171 is outside (0, 170] degrees' "$work/stderr" && ok || fail "fov message: $(cat "$work/stderr")"
expect_usage_error "fov not a number" render --camera pinhole --fov wide
expect_usage_error "look elevation beyond 90" render --camera pinhole --look-elevation 91
grep -q -- '--look-elevation: 91 is outside \[-90, 90\] degrees' "$work/stderr" && ok || fail "look-elevation message: $(cat "$work/stderr")"
expect_usage_error "look elevation beyond -90" render --camera pinhole --look-elevation -90.5
expect_usage_error "look azimuth out of range" render --camera pinhole --look-azimuth 400
expect_usage_error "aspect with an empty side" render --camera pinhole --aspect 16:
expect_usage_error "aspect zero" render --camera pinhole --aspect 0
expect_usage_error "aspect negative" render --camera pinhole --aspect -1.5
expect_usage_error "aspect not a ratio" render --camera pinhole --aspect wide
grep -q -- "--aspect: 'wide' is not a ratio W:H or a positive number" "$work/stderr" && ok || fail "aspect message: $(cat "$work/stderr")"
expect_usage_error "aspect too wide for the width" render --camera pinhole --width 64 --aspect 20:1
grep -q -- '--aspect: 20 gives a height of 4 pixels for width 64, outside \[8, 16384\]' "$work/stderr" && ok || fail "aspect height message: $(cat "$work/stderr")"
expect_usage_error "fov with equirect" render --fov 60
grep -q -- '--fov: applies only to --camera pinhole' "$work/stderr" && ok || fail "fov with equirect: $(cat "$work/stderr")"
expect_usage_error "look direction with fisheye" render --camera fisheye --look-azimuth 90
expect_usage_error "aspect with equirect" render --camera equirect --aspect 4:3
expect_usage_error "fisheye projection with pinhole" render --camera pinhole --fisheye-projection equisolid
grep -q -- '--fisheye-projection: applies only to --camera fisheye' "$work/stderr" && ok || fail "projection with pinhole: $(cat "$work/stderr")"
expect_usage_error "fisheye projection without a camera" render --fisheye-projection equidistant
# sizes, and the camera in the sidecar and the EXR header
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --camera fisheye --fisheye-projection equisolid --width 24 --quality preview --sample-scale 0.1 --progress none \
    -o "$work/out/fish.exr" 2>"$work/stderr" && ok || fail "fisheye render: $(cat "$work/stderr")"
"$FM" render --camera pinhole --fov 60 --look-azimuth 200 --look-elevation 10 --aspect 16:9 --width 32 --quality preview \
    --sample-scale 0.1 --progress none -o "$work/out/pin.exr" 2>"$work/stderr" && ok || fail "pinhole render: $(cat "$work/stderr")"
"$FM" render --camera pinhole --aspect 1.5 --width 30 --quality preview --sample-scale 0.1 --progress none \
    -o "$work/out/pin15.exr" 2>"$work/stderr" && ok || fail "pinhole render with a numeric aspect: $(cat "$work/stderr")"
tr -d ' \t\n' <"$work/out/fish.json" >"$work/fish.flat"
tr -d ' \t\n' <"$work/out/pin.json" >"$work/pin.flat"
tr -d ' \t\n' <"$work/out/pin15.json" >"$work/pin15.flat"
grep -q '"width":24,"height":24,"projection":"fisheyeequisolid"' "$work/fish.flat" && ok || fail "fisheye image keys: $(head -c 300 "$work/fish.flat")"
grep -q '"camera":{"type":"fisheye","fisheye_projection":"equisolid","field_of_view_deg":180}' "$work/fish.flat" && ok ||
    fail "fisheye camera keys: $(grep -o '"camera":{[^}]*}' "$work/fish.flat")"
grep -q '"diffuse_horizontal_illuminance_lux"' "$work/fish.flat" && ok || fail "a fisheye holds the hemisphere: diffuse illuminance"
grep -q '"width":32,"height":18,"projection":"pinhole(rectilinear)"' "$work/pin.flat" && ok || fail "pinhole image keys: $(head -c 300 "$work/pin.flat")"
grep -q '"camera":{"type":"pinhole","horizontal_fov_deg":60,"vertical_fov_deg":35.' "$work/pin.flat" &&
    grep -q '"look_azimuth_deg":200,"look_elevation_deg":10,"look_direction":\[' "$work/pin.flat" && ok ||
    fail "pinhole camera keys: $(grep -o '"camera":{[^}]*}' "$work/pin.flat")"
! grep -q '"diffuse_horizontal' "$work/pin.flat" && ok || fail "a pinhole view reports no diffuse horizontal irradiance"
grep -q '"width":30,"height":20,' "$work/pin15.flat" && ok || fail "pinhole --aspect 1.5: $(head -c 200 "$work/pin15.flat")"
if command -v exrheader >/dev/null; then
    exrheader "$work/out/fish.exr" >"$work/fish.header"
    grep -q 'firmament.camera.type (type string): "fisheye"' "$work/fish.header" && ok || fail "EXR camera attribute"
    ! grep -q '^envmap' "$work/fish.header" && ok || fail "a fisheye is no latlong environment map"
    "$FM" render --width 16 --quality preview --sample-scale 0.1 --progress none -o "$work/out/map.exr" &&
        exrheader "$work/out/map.exr" | grep -q '^envmap.*latitude-longitude' && ok || fail "the equirect map keeps envmap = latlong"
fi

# --- interruption: SIGINT and SIGTERM leave nothing, and never replace an existing file ---------
interrupt() {
    local sig=$1 expect=$2
    rm -rf "$work/out" && mkdir -p "$work/out"
    printf 'previous image' >"$work/out/sky.exr"
    printf 'previous sidecar' >"$work/out/sky.json"
    "$FM" render --width 1024 --quality final --progress none -o "$work/out/sky.exr" &
    local pid=$!
    # wait until the render has started (its temporary files exist), then interrupt it
    for _ in $(seq 1 100); do
        [ "$(ls -A "$work/out" | wc -l)" -gt 2 ] && break
        sleep 0.05
    done
    sleep 0.5
    kill -"$sig" $pid
    wait $pid
    local rc=$?
    [ $rc -eq "$expect" ] && ok || fail "SIG$sig: exit $rc, expected $expect"
    [ "$(cat "$work/out/sky.exr")" = "previous image" ] && [ "$(cat "$work/out/sky.json")" = "previous sidecar" ] && ok ||
        fail "SIG$sig replaced the existing files"
    [ "$(ls -A "$work/out" | wc -l)" -eq 2 ] && ok || fail "SIG$sig left files: $(ls -A "$work/out")"
}
interrupt INT 130
interrupt TERM 143

echo "$checks checks passed, $failures failed"
[ $failures -eq 0 ]

#!/usr/bin/env bash
# The firmament executable's behaviour: exit codes, one-line messages naming the problem, outputs
# written completely or not at all (errors, SIGINT, SIGTERM), progress lines, `compare`.
# Usage: test_cli.sh path/to/firmament
set -u
FM=$(realpath "$1") # absolute: the cases run from their own directories
here=$(cd "$(dirname "$0")" && pwd)
. "$here/harness.sh"

# --- help and version -------------------------------------------------------------------------
"$FM" --help >"$work/help" 2>&1 && grep -q -- '--sun-elevation' "$work/help" && ok || fail "--help"
"$FM" render --help >"$work/help" 2>&1 && grep -q -- '--wavelength' "$work/help" && ok || fail "render --help"
# "firmament 0.2.0 (abc1234, release, linux-x64)": the version is CMake's project VERSION
version=$(sed -n 's/^project(firmament VERSION \([0-9.]*\) .*/\1/p' "$here/../../CMakeLists.txt")
"$FM" --version | grep -Eq "^firmament ${version//./\\.} \(([0-9a-f]{7}(-dirty)?|unknown), [a-z]+, [a-z]+-[a-z0-9]+\)$" && ok ||
    fail "--version: $("$FM" --version)"

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
# a name or path holding a newline stays on the error's one line, the newline escaped
expect_usage_error "unknown biome with a newline" render --biome $'jun\ngle'
if grep -qF "'jun\ngle'" "$work/stderr"; then ok; else fail "newline not escaped: $(cat "$work/stderr")"; fi
expect_usage_error "unwritable output with a newline" render --width 8 -o $'/nonexistent/a\nb.exr'
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
# numbers and dates as people write them: no spaces, signs inside a date, hexadecimal or infinity
expect_usage_error "date with a signed month" render --date 2024-+1-01 --latitude 45
expect_usage_error "date with a space" render --date "2024- 1-01" --latitude 45
expect_usage_error "number with a leading space" render --width " 64"
expect_usage_error "hexadecimal whole number" render --width 0x40
expect_usage_error "hexadecimal number" render --turbidity 0x1
expect_usage_error "infinite number" render --sun-elevation inf
expect_usage_error "exponent without digits" render --sun-elevation 1e
expect_usage_error "sun: hexadecimal latitude" sun --date 2023-06-01 --time 12:00 --latitude 0x2d --longitude 7
# options that would do nothing, and a path left out (the next option taken for it)
expect_usage_error "latitude without a date" render --latitude 45
expect_usage_error "longitude without a date" render --longitude 7
expect_usage_error "samples without reference quality" render --samples 64
expect_usage_error "output that is an option" render --width 16 -o --width 16
expect_usage_error "preview that is an option" render --width 16 --preview --half
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
grep -qF -- "--atmosphere: $work/bad-g.json: \$.constituents[0].phase.g: must be in [-0.99999, 0.99999], not 1.5" "$work/stderr" && ok ||
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
# a file name of 251 bytes (of the 255 a name may have): its temporary file's name is cut short
long=$(printf 'a%.0s' $(seq 1 247)).exr
mkdir -p "$work/long"
if "$FM" render --width 8 --quality preview --progress none -o "$work/long/$long" 2>"$work/stderr" &&
    [ -s "$work/long/$long" ] && [ "$(ls -A "$work/long" | wc -l)" -eq 2 ]; then ok; else
    fail "a 251-byte file name: $(cat "$work/stderr") $(ls -A "$work/long")"
fi
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
"$FM" compare "$work/out/sky.exr" "$work/out/sky.exr" --exclude-sun 0x5 >/dev/null 2>"$work/stderr"
[ $? -eq 2 ] && grep -q "'0x5' is not an angle" "$work/stderr" && ok || fail "compare: hexadecimal angle: $(cat "$work/stderr")"

# --- the sun from the date and time (firmament sun, render --time, time series) -----------------
grep -q -- '--utc-offset' "$work/help" && ok || fail "render --help lists --utc-offset"
sunargs=(--date 2003-10-17 --time 12:30:30 --utc-offset -07:00 --latitude 39.742476 --longitude -105.1786)
# SPA's published example (Reda & Andreas 2004): zenith 50.11162, azimuth 194.34024
"$FM" sun "${sunargs[@]}" --altitude 1830.14 --pressure 820 --temperature 11 --delta-t 67 --json >"$work/sun.json" 2>"$work/stderr" && ok ||
    fail "sun: $(cat "$work/stderr")"
python3 - "$work/sun.json" <<'PY' && ok || fail "sun --json values: $(cat "$work/sun.json")"
import json, sys
d = json.load(open(sys.argv[1]))
assert abs(d["zenith_deg"] - 50.11162) < 1e-3 and abs(d["azimuth_deg"] - 194.34024) < 1e-3, d
assert d["day"] == "normal" and d["sunrise"] == "06:12:43" and d["solar_noon"] == "11:46:05", d
assert abs(d["earth_sun_distance_au"] - 0.996542) < 1e-6 and d["refraction"] is True, d
PY
"$FM" sun "${sunargs[@]}" | grep -q '^azimuth  *194\.34' && ok || fail "sun text output"
# polar night and polar day at Longyearbyen: reported, exit 0
"$FM" sun --date 2023-12-21 --time 12:00 --utc-offset +01:00 --latitude 78.2 --longitude 15.6 >"$work/out.txt" 2>&1 &&
    grep -q '^sunrise  *none (polar night)' "$work/out.txt" && grep -q '^sunset  *none (polar night)' "$work/out.txt" && ok ||
    fail "polar night: $(cat "$work/out.txt")"
"$FM" sun --date 2023-06-21 --time 12:00 --utc-offset +02:00 --latitude 78.2 --longitude 15.6 --json >"$work/out.txt" 2>&1 &&
    grep -q '"day": "polar day"' "$work/out.txt" && grep -q '"sunrise": null' "$work/out.txt" && grep -q '"sunset": null' "$work/out.txt" && ok ||
    fail "polar day: $(cat "$work/out.txt")"
# bad input: exit 2 and one line naming the problem
for bad in "--date 2023-02-30" "--date 2023-13-01" "--time 25:00" "--time 12:61" "--utc-offset +15:00" "--utc-offset abc" \
    "--latitude 90.5" "--longitude 181" "--refraction maybe" "--pressure -5"; do
    # shellcheck disable=SC2086
    expect_usage_error "sun $bad" sun --date 2023-06-01 --time 12:00 --latitude 45 --longitude 7 $bad
    grep -q -- "${bad%% *}" "$work/stderr" && ok || fail "sun $bad: message names ${bad%% *}: $(cat "$work/stderr")"
done
expect_usage_error "sun without --time" sun --date 2023-06-01 --latitude 45 --longitude 7
r=(render --width 16 --quality preview)
for bad in "--date 2023-02-30" "--date 2023-13-01" "--time 25:00" "--time 12:61" "--utc-offset +15:00" "--utc-offset abc" \
    "--latitude 91" "--longitude -181"; do
    # shellcheck disable=SC2086
    expect_usage_error "render $bad" "${r[@]}" --date 2023-06-01 --time 12:00 --latitude 45 --longitude 7 $bad
    grep -q -- "${bad%% *}" "$work/stderr" && ok || fail "render $bad: message names ${bad%% *}: $(cat "$work/stderr")"
done
expect_usage_error "--time without --date" "${r[@]}" --time 12:00 --latitude 45 --longitude 7
grep -q -- '--time: needs --date' "$work/stderr" && ok || fail "time without date: $(cat "$work/stderr")"
expect_usage_error "--time without --latitude" "${r[@]}" --date 2023-06-01 --time 12:00 --longitude 7 --ozone-du 300
grep -q -- '--time: needs --latitude and --longitude' "$work/stderr" && ok || fail "time without latitude: $(cat "$work/stderr")"
expect_usage_error "--refraction without a time" "${r[@]}" --refraction off
expect_usage_error "time-start after time-end" "${r[@]}" --date 2023-06-01 --latitude 45 --longitude 7 --time-start 18:00 --time-end 06:00 --step 60
grep -q -- '--time-start: 18:00:00 is after --time-end 06:00:00' "$work/stderr" && ok || fail "start after end: $(cat "$work/stderr")"
expect_usage_error "step 0" "${r[@]}" --date 2023-06-01 --latitude 45 --longitude 7 --time-start 06:00 --time-end 18:00 --step 0
expect_usage_error "negative step" "${r[@]}" --date 2023-06-01 --latitude 45 --longitude 7 --time-start 06:00 --time-end 18:00 --step -5
expect_usage_error "more than 10000 frames" "${r[@]}" --date 2023-06-01 --latitude 45 --longitude 7 --time-start 00:00 --time-end 23:59 --step 0.1
grep -q 'makes 14391 frames (at most 10000)' "$work/stderr" && ok || fail "frame count: $(cat "$work/stderr")"
expect_usage_error "--time with a series" "${r[@]}" --date 2023-06-01 --latitude 45 --longitude 7 --time 12:00 --time-start 06:00 --time-end 18:00 --step 60
expect_usage_error "series without --step" "${r[@]}" --date 2023-06-01 --latitude 45 --longitude 7 --time-start 06:00 --time-end 18:00

# render --time: the sidecar records the time and the computed sun (apparent elevation)
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" "${r[@]}" "${sunargs[@]}" --progress none -o "$work/out/golden.exr" 2>"$work/stderr" && ok || fail "render --time: $(cat "$work/stderr")"
python3 - "$work/out/golden.json" <<'PY' && ok || fail "render --time sidecar: $(cat "$work/out/golden.json")"
import json, sys
d = json.load(open(sys.argv[1]))
p, s, sp = d["parameters"], d["sun"], d["solar_position"]
assert p["date"] == "2003-10-17" and p["time"] == "12:30:30" and p["utc_offset"] == "-07:00" and p["refraction"] == "on", p
assert abs(s["elevation_deg"] - sp["elevation_deg"]) < 1e-12 and sp["elevation_deg"] > sp["elevation_without_refraction_deg"], sp
assert abs(sp["elevation_without_refraction_deg"] - 39.8720) < 2e-3 and abs(sp["azimuth_deg"] - 194.3402) < 2e-3, sp
assert sp["used_for"] == "elevation, azimuth, earth_sun_distance" and abs(p["earth_sun_distance_au"] - 0.99654) < 2e-4, p
PY
# given --sun-elevation/--sun-azimuth override the time
"$FM" "${r[@]}" "${sunargs[@]}" --sun-elevation 12 --sun-azimuth 100 --refraction off --progress none -o "$work/out/given.exr" &&
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["sun"]["elevation_deg"] == 12 and d["sun"]["azimuth_deg"] == 100 and d["solar_position"]["used_for"] == "earth_sun_distance" and d["parameters"]["refraction"] == "off", d' "$work/out/given.json" &&
    ok || fail "--sun-elevation overrides --time"

# the Earth-Sun distance is the date's whether the sun comes from --time or from its angles (the
# add-on's Live mode switches between them): the map of a --time and the map of the same sun given
# by the angles its sidecar reports, on that date, are the same; no date gives 1 AU, a given one stays
dated=(--date 2024-01-03 --latitude 48.8566 --longitude 2.3522)
"$FM" "${r[@]}" "${dated[@]}" --time 10:00 --utc-offset +01:00 --progress none -o "$work/out/clock.exr" &&
    read -r elev azim < <(python3 -c 'import json,sys; s=json.load(open(sys.argv[1]))["sun"]; print(repr(s["elevation_deg"]), repr(s["azimuth_deg"]))' "$work/out/clock.json") &&
    "$FM" "${r[@]}" "${dated[@]}" --sun-elevation "$elev" --sun-azimuth "$azim" --progress none -o "$work/out/angles.exr" &&
    "$FM" "${r[@]}" --sun-elevation "$elev" --sun-azimuth "$azim" --progress none -o "$work/out/undated.exr" &&
    "$FM" "${r[@]}" "${dated[@]}" --sun-elevation "$elev" --earth-sun-distance 1.01 --progress none -o "$work/out/given.exr" &&
    "$FM" compare "$work/out/clock.exr" "$work/out/angles.exr" | grep -q '^max relative  0.0000 %' &&
    python3 - "$work/out" <<'PY' && ok || fail "the date's Earth-Sun distance with --time and with sun angles"
import json, sys
side = {n: json.load(open(f"{sys.argv[1]}/{n}.json")) for n in ("clock", "angles", "undated", "given")}
p = {n: d["parameters"] for n, d in side.items()}
# near perihelion (2024-01-03 00:39 UT, 0.98331 AU: JPL Horizons)
assert abs(p["clock"]["earth_sun_distance_au"] - 0.98331) < 1e-4 and p["clock"]["earth_sun_distance_from"] == "date", p
assert p["angles"]["earth_sun_distance_au"] == p["clock"]["earth_sun_distance_au"] and p["angles"]["earth_sun_distance_from"] == "date", p
assert side["angles"]["sky"] == side["clock"]["sky"], side
assert p["undated"]["earth_sun_distance_au"] == 1 and p["undated"]["earth_sun_distance_from"] == "mean (no date)", p
assert p["given"]["earth_sun_distance_au"] == 1.01 and p["given"]["earth_sun_distance_from"] == "given", p
PY

# deep twilight's final maps take more paths per multiple-scattering node (render.c: 1x at sun -11
# deg, 2x at -18, 1x again by -21), the preview its own; the sidecar and the EXR say how many
# (2048 x 1/64 = 32; the default sky's table needs no second pass, twilight_extra_paths)
for c in "-18 final 64" "-14.5 final 48" "-8 final 32" "-19.5 final 48" "-21 final 32" "-18 preview 8"; do
    set -- $c
    "$FM" render --width 16 --quality "$2" --sun-elevation "$1" --sample-scale 0.015625 --progress none -o "$work/out/tw.exr" &&
        python3 -c 'import json,sys; p=json.load(open(sys.argv[1]))["parameters"]; assert p["paths_per_node"] == int(sys.argv[2]), p' \
            "$work/out/tw.json" "$3" && "$FM" info "$work/out/tw.exr" | grep -q "paths_per_node (int): $3\$" &&
        ok || fail "paths per node at sun $1, $2 quality: $(grep paths_per_node "$work/out/tw.json")"
done

# a time series: numbered maps and sidecars, each with its own time and sun; a night frame is reported
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" "${r[@]}" --date 2023-06-21 --utc-offset +02:00 --latitude 48.8566 --longitude 2.3522 --time-start 00:30 --time-end 12:30 \
    --step 240 --progress json -o "$work/out/day.exr" >"$work/progress" 2>"$work/stderr" && ok || fail "time series: $(cat "$work/stderr")"
[ "$(ls "$work/out" | tr '\n' ' ')" = "day_0000.exr day_0000.json day_0001.exr day_0001.json day_0002.exr day_0002.json day_0003.exr day_0003.json " ] && ok ||
    fail "time series files: $(ls "$work/out")"
tail -n 1 "$work/progress" | grep -q '"event": "done", "frames": 4' && ok || fail "series done event: $(tail -n 1 "$work/progress")"
grep -c '"event": "frame_done"' "$work/progress" | grep -qx 4 && ok || fail "four frame_done events"
for i in 0 1 2 3; do
    t=$(printf '%02d:30' $((4 * i)))
    "$FM" sun --date 2023-06-21 --time "$t" --utc-offset +02:00 --latitude 48.8566 --longitude 2.3522 --json >"$work/sun$i.json"
done
python3 - "$work/out" "$work" <<'PY' && ok || fail "series sidecars carry each frame's time and sun"
import json, sys
for i, t in enumerate(["00:30:00", "04:30:00", "08:30:00", "12:30:00"]):
    d = json.load(open("%s/day_%04d.json" % (sys.argv[1], i)))
    ref = json.load(open("%s/sun%d.json" % (sys.argv[2], i)))
    assert d["parameters"]["time"] == t and d["image"]["file"] == "day_%04d.exr" % i, d["parameters"]
    assert abs(d["sun"]["elevation_deg"] - ref["elevation_deg"]) < 1e-5, (d["sun"], ref)
    assert abs(d["sun"]["azimuth_deg"] - ref["azimuth_deg"]) < 1e-5, (d["sun"], ref)
PY
# 00:30 in Paris in June: the sun about 17 deg down, not yet night; a December night frame is flagged
grep '"event": "frame"' "$work/progress" | head -n 1 | grep -q '"night": false' && ok || fail "June night is twilight"
"$FM" "${r[@]}" --date 2023-12-21 --utc-offset +01:00 --latitude 48.8566 --longitude 2.3522 --time-start 00:00 --time-end 00:00 \
    --step 60 --progress json -o "$work/out/dec.exr" >"$work/progress" 2>&1 &&
    grep -q '"night": true' "$work/progress" && grep -q '"night_frames": 1' "$work/progress" && [ -s "$work/out/dec_0000.exr" ] && ok ||
    fail "a night frame renders and is reported: $(cat "$work/progress")"
# the series frame is the same map as a separate run at that time
"$FM" "${r[@]}" --date 2023-06-21 --utc-offset +02:00 --latitude 48.8566 --longitude 2.3522 --time 08:30 --progress none -o "$work/out/single.exr" &&
    "$FM" compare "$work/out/day_0002.exr" "$work/out/single.exr" --json | grep -q '"max": 0,' && ok || fail "series frame = separate run"
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
grep -q -- '--aspect: width 64 / aspect 20 gives a height of 4 pixels, outside \[8, 16384\]' "$work/stderr" && ok || fail "aspect height message: $(cat "$work/stderr")"
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

# --- colour spaces (OpenColorIO) ---------------------------------------------------------------
"$FM" render --list-colorspaces >"$work/spaces" 2>&1 && grep -qx 'Linear Rec.709' "$work/spaces" &&
    grep -qx 'ACEScg' "$work/spaces" && grep -qx 'CIE XYZ D65' "$work/spaces" && ok || fail "--list-colorspaces: $(cat "$work/spaces")"
expect_usage_error "unknown colour space" render --width 16 --quality preview --colorspace Rec.2020
grep -q '"ACEScg"' "$work/stderr" && grep -q '"Linear Rec.709"' "$work/stderr" && ok || fail "unknown colour space lists the names: $(cat "$work/stderr")"
expect_usage_error "display-encoded colour space" render --width 16 --quality preview --colorspace sRGB
printf 'ocio_profile_version: 2\ncolorspaces: [broken\n' >"$work/broken.ocio"
OCIO="$work/broken.ocio" expect_usage_error "broken \$OCIO" render --width 16 --quality preview
grep -q "broken.ocio" "$work/stderr" && ok || fail "broken \$OCIO names the file: $(cat "$work/stderr")"
# the EXR's chromaticities and the sidecar follow the chosen space; luminance is the same
rm -rf "$work/out" && mkdir -p "$work/out"
for cs in "Linear Rec.709" ACEScg "CIE XYZ D65"; do
    "$FM" render --width 32 --quality preview --progress none --colorspace "$cs" -o "$work/out/${cs// /_}.exr" || fail "render --colorspace $cs"
done
python3 - "$work/out" <<'PY' && ok || fail "colour spaces: chromaticities, sidecar colorspace and luminance"
import json, struct, sys
d = sys.argv[1]
def chromaticities(path):
    data = open(path, "rb").read()
    i = 8
    while data[i] != 0:
        name_end = data.index(b"\0", i); typ_end = data.index(b"\0", name_end + 1)
        name, typ = data[i:name_end].decode(), data[name_end + 1:typ_end].decode()
        size = struct.unpack("<i", data[typ_end + 1:typ_end + 5])[0]
        value = data[typ_end + 5:typ_end + 5 + size]
        if name == "chromaticities":
            return struct.unpack("<8f", value)
        i = typ_end + 5 + size
expect = {"Linear_Rec.709": (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290),
          "CIE_XYZ_D65": (1, 0, 0, 1, 0, 0, 1 / 3, 1 / 3)}
for name, e in expect.items():
    c = chromaticities(f"{d}/{name}.exr")
    assert all(abs(a - b) < 1e-5 for a, b in zip(c, e)), (name, c)
c = chromaticities(f"{d}/ACEScg.exr")
assert abs(c[6] - 0.3127) < 1e-4 and abs(c[7] - 0.3290) < 1e-4, c  # Bradford: white stays D65
lux = []
for name in ("Linear_Rec.709", "ACEScg", "CIE_XYZ_D65"):
    j = json.load(open(f"{d}/{name}.json"))
    assert j["image"]["colorspace"] == name.replace("_", " "), j["image"]
    lux.append(j["sky"]["diffuse_horizontal_illuminance_lux"])
assert max(lux) - min(lux) < 1e-4 * max(lux), lux
# the sidecar's RGB is in the chosen space: in XYZ the middle value is Y, 683 Y = lux
j = json.load(open(f"{d}/CIE_XYZ_D65.json"))
assert abs(683 * j["sun"]["direct_normal_irradiance_rgb"][1] - j["sun"]["direct_normal_illuminance_lux"]) < 1e-3 * j["sun"]["direct_normal_illuminance_lux"], j["sun"]
PY
# compare reads each file's colour space from its chromaticities: the same sky in ACEScg and in XYZ
for cs in ACEScg CIE_XYZ_D65; do
    "$FM" compare "$work/out/$cs.exr" "$work/out/Linear_Rec.709.exr" --json >"$work/cmp" &&
        python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["max"] < 1e-3 and d["chromaticity"] < 1e-4, d' "$work/cmp" &&
        ok || fail "compare $cs with Linear Rec.709: $(cat "$work/cmp")"
done

# --- previews ------------------------------------------------------------------------------------
expect_usage_error "--exposure without --preview" render --width 16 --quality preview --exposure 2
expect_usage_error "--exposure out of range" render --width 16 --quality preview --preview p.png --exposure 1000
expect_usage_error "--exposure not a number" render --width 16 --quality preview --preview p.png --exposure bright
expect_usage_error "--preview with --wavelength" render --width 16 --quality preview --preview p.png --wavelength 550
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 32 --quality preview --progress none --preview "$work/out/sky.png" -o "$work/out/sky.exr" &&
    "$FM" render --width 32 --quality preview --progress none --preview "$work/out/dark.png" --exposure -20 -o "$work/out/dark.exr" &&
    python3 - "$work/out" <<'PY' && ok || fail "--preview writes a 32 x 16 8-bit RGB PNG; --exposure -20 is black"
import struct, sys, zlib
d = sys.argv[1]
def png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    i, idat, hdr = 8, b"", None
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        body = data[i + 8:i + 8 + n]
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBB", body[:10])
        if kind == b"IDAT":
            idat += body
        i += 12 + n
    return hdr, zlib.decompress(idat)
hdr, _ = png(f"{d}/sky.png")
assert hdr == (32, 16, 8, 2), hdr
hdr, raw = png(f"{d}/dark.png")
assert len(raw) == 16 * (1 + 96) and sum(raw) < 100, sum(raw)  # black but for a few sun-disk codes
import os
assert sorted(os.listdir(d)) == ["dark.exr", "dark.json", "dark.png", "sky.exr", "sky.json", "sky.png"], os.listdir(d)
PY

# --- half-float and compression -----------------------------------------------------------------
expect_usage_error "unknown compression" render --width 16 --quality preview --compression lzma
# DWAA quantises through half precision: the sun disk is refused (nothing written), the sky alone is
# written, read back by compare (OpenEXR's C++ library decodes it) and named by info
expect_usage_error "dwaa with the sun disk" render --width 256 --quality preview --sample-scale 0.05 --compression dwaa
grep -q -- '--compression: dwaa: .*65504.*--no-sun-disk' "$work/stderr" && ok || fail "dwaa overflow message: $(cat "$work/stderr")"
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 64 --quality preview --progress none --no-sun-disk --compression dwaa -o "$work/out/dwaa.exr" &&
    "$FM" render --width 64 --quality preview --progress none --no-sun-disk -o "$work/out/zip.exr" &&
    "$FM" compare "$work/out/dwaa.exr" "$work/out/zip.exr" --json >"$work/cmp" &&
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert 0 < d["rms"] < 5e-3, d' "$work/cmp" &&
    "$FM" info "$work/out/dwaa.exr" | grep -q '^compression (compression): dwaa' && ok ||
    fail "--compression dwaa: written, compared, named by info: $(cat "$work/cmp")"
# at 256 pixels across the sun disk exceeds the half range: refused after the render, nothing written
expect_usage_error "--half with the sun disk" render --width 256 --quality preview --sample-scale 0.05 --half
grep -q -- '--half: .*65504.*--no-sun-disk' "$work/stderr" && ok || fail "half overflow message: $(cat "$work/stderr")"
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 32 --quality preview --progress none --no-sun-disk --half --compression piz -o "$work/out/half.exr" &&
    "$FM" render --width 32 --quality preview --progress none --no-sun-disk -o "$work/out/float.exr" &&
    "$FM" compare "$work/out/half.exr" "$work/out/float.exr" --json >"$work/cmp" &&
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["max"] < 1e-3, d' "$work/cmp" && ok ||
    fail "--half --compression piz: readable and within half precision of float: $(cat "$work/cmp")"

# --- spectral EXR --------------------------------------------------------------------------------
expect_usage_error "--spectral with --wavelength" render --width 16 --quality preview --spectral s.exr --wavelength 550
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 32 --quality preview --progress none --spectral "$work/out/spectral.exr" -o "$work/out/sky.exr" &&
    "$FM" render --width 32 --quality preview --progress none -o "$work/out/plain.exr" &&
    [ -s "$work/out/spectral.exr" ] && [ "$(ls -A "$work/out" | wc -l)" -eq 5 ] &&
    "$FM" compare "$work/out/sky.exr" "$work/out/plain.exr" --json >"$work/cmp" &&
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["max"] < 1e-3, d' "$work/cmp" && ok ||
    fail "--spectral writes the spectral EXR beside the same RGB map: $(ls -A "$work/out") $(cat "$work/cmp" 2>/dev/null)"
"$FM" compare "$work/out/spectral.exr" "$work/out/sky.exr" >/dev/null 2>"$work/stderr"
[ $? -ne 0 ] && grep -q 'found 41 channels' "$work/stderr" && ok || fail "compare refuses a spectral EXR: $(cat "$work/stderr")"
grep -q 'S0.550,000000nm' "$work/out/spectral.exr" && grep -q 'W.m^-2.sr^-1.nm^-1' "$work/out/spectral.exr" && ok ||
    fail "spectral EXR channel names and emissiveUnits"

# --- info: the EXR's header ----------------------------------------------------------------------
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 16 --quality preview --progress none --colorspace ACEScg -o "$work/out/sky.exr" &&
    "$FM" info "$work/out/sky.exr" >"$work/info" && grep -q '^compression (compression): piz$' "$work/info" &&
    grep -q '^chromaticities (chromaticities): red' "$work/info" && grep -q '^envmap (envmap): latlong$' "$work/info" &&
    grep -q '^firmament.image.colorspace (string): ACEScg$' "$work/info" &&
    grep -q '^firmament.sun.direction (v3d): (' "$work/info" && ok || fail "info lists the header: $(cat "$work/info")"
[ "$(grep -n '^firmament' "$work/info" | head -n 1 | cut -d: -f1)" -gt "$(grep -n '^whiteLuminance' "$work/info" | cut -d: -f1)" ] &&
    ok || fail "info: standard attributes first"
expect_usage_error "info without a file" info
expect_usage_error "info of a missing file" info missing.exr
grep -q "missing.exr" "$work/stderr" && ok || fail "info names the missing file: $(cat "$work/stderr")"

# --- every output checked before the render: writable, a regular file, no two the same ----------
R=(render --width 16 --quality preview --progress none)
SERIES=(--date 2024-06-21 --latitude 45 --longitude 7 --time-start 10:00 --time-end 11:00 --step 30)
expect_usage_error "-o and --preview one file" "${R[@]}" -o o.exr --preview o.exr
grep -qF -- "-o and --preview would both write 'o.exr'" "$work/stderr" && ok || fail "same-file message: $(cat "$work/stderr")"
expect_usage_error "--spectral is the sidecar, spelled otherwise" "${R[@]}" -o o.exr --spectral ./o.json
expect_usage_error "--preview is the sidecar" "${R[@]}" -o o.exr --sidecar p.png --preview p.png
expect_usage_error "--sun-disk-map's sidecar is the map's" "${R[@]}" -o a.exr --sun-disk-map a.tif
printf 'x' >"$work/afile"
expect_usage_error "--preview under a file" "${R[@]}" -o o.exr --preview "$work/afile/p.png"
grep -qF -- "--preview: cannot write '$work/afile/p.png'" "$work/stderr" && ok || fail "preview path message: $(cat "$work/stderr")"
expect_usage_error "--spectral in a missing directory" "${R[@]}" -o o.exr --spectral /nonexistent/s.exr
expect_usage_error "--preview a directory" "${R[@]}" -o o.exr --preview "$work"
expect_usage_error "--preview empty" "${R[@]}" -o o.exr --preview ""
# run as root, `-o /dev/null` would have replaced the device by the map: an existing non-file is refused
mkfifo "$work/fifo"
expect_usage_error "-o a FIFO" "${R[@]}" -o "$work/fifo" --sidecar s.json
[ -p "$work/fifo" ] && ok || fail "-o a FIFO: the FIFO was replaced"
mkdir -p "$work/sdir"
expect_usage_error "series into a directory" "${R[@]}" "${SERIES[@]}" -o "$work/sdir"
[ -z "$(ls "$work" | grep '^sdir_')" ] && ok || fail "series into a directory wrote beside it: $(ls "$work")"
expect_usage_error "series preview over its maps" "${R[@]}" "${SERIES[@]}" -o s.exr --preview s.exr
expect_usage_error "empty biome name" "${R[@]}" --biome ""
expect_usage_error "--aod550 and --turbidity" "${R[@]}" --aod550 0.3 --turbidity 2
grep -qF -- "--aod550: give turbidity or aod550, not both" "$work/stderr" && ok || fail "aod550 conflict: $(cat "$work/stderr")"
FIRMAMENT_PRESETS=/nonexistent expect_usage_error "FIRMAMENT_PRESETS not a directory" "${R[@]}"
grep -qF "FIRMAMENT_PRESETS: '/nonexistent' is not a directory" "$work/stderr" && ok || fail "presets message: $(cat "$work/stderr")"
expect_usage_error "--step making absurdly many frames" "${R[@]}" --date 2024-06-21 --latitude 45 --longitude 7 \
    --time-start 10:00 --time-end 11:00 --step 1e-300
[ "$(wc -c <"$work/stderr")" -lt 200 ] && ok || fail "frame count printed in full: $(cat "$work/stderr")"
# getopt's abbreviations would read --pres (a typo of --preset) as --pressure: full names only
expect_usage_error "abbreviated option" "${R[@]}" --pres golden-hour
grep -qF -- "unknown option '--pres' (options are given in full: --pressure?)" "$work/stderr" && ok ||
    fail "abbreviation message: $(cat "$work/stderr")"
expect_usage_error "abbreviated option with =" "${R[@]}" --sun-elev=10
expect_usage_error "a value to a flag" "${R[@]}" --no-sun-disk=1
grep -qF -- "--no-sun-disk takes no value" "$work/stderr" && ok || fail "flag with a value: $(cat "$work/stderr")"
# output that cannot reach stdout is an error
"$FM" sun --date 2024-06-21 --time 12:00 --latitude 45 --longitude 7 --json >/dev/full 2>"$work/stderr"
[ $? -eq 1 ] && grep -q '^firmament: cannot write to standard output' "$work/stderr" && ok ||
    fail "sun into /dev/full: $(cat "$work/stderr")"
# a reader that goes away (SIGPIPE) stops the render like Ctrl-C: no temporary file left
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 256 --quality preview --progress json -o "$work/out/o.exr" 2>/dev/null | head -n 1 >/dev/null
rc=${PIPESTATUS[0]}
[ "$rc" -eq 141 ] && ok || fail "SIGPIPE: exit $rc, expected 141"
expect_empty_dir "SIGPIPE"
# Ctrl-C while the spectral map is written: the map, sidecar and preview are not left either
rm -rf "$work/out" && mkdir -p "$work/out"
"$FM" render --width 1024 --quality preview --sample-scale 0.1 --progress json -o "$work/out/sky.exr" \
    --spectral "$work/out/s.exr" --preview "$work/out/p.png" >"$work/progress" 2>/dev/null &
pid=$!
for _ in $(seq 1 3000); do grep -q '"stage": "done"' "$work/progress" && break; sleep 0.01; done
for _ in $(seq 1 1000); do ls -A "$work/out" | grep -q '^\.s\.exr\.' && break; sleep 0.01; done
kill -INT $pid
wait $pid
rc=$?
[ $rc -eq 130 ] && ok || fail "SIGINT during the spectral map: exit $rc, expected 130"
expect_empty_dir "SIGINT during the spectral map"

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

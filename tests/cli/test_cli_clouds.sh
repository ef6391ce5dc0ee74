#!/usr/bin/env bash
# Clouds from the command line (docs/clouds.md): --cloud and its numbers, --fog-visibility, cloud JSON
# files, a sky preset and a custom atmosphere declaring clouds; the sidecar's optical depths and the
# sun's transmittance; bad input refused with one line.
# Usage: test_cli_clouds.sh path/to/firmament
set -u
FM=$(realpath "$1")
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
. "$here/harness.sh"

json_get() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval('d' + sys.argv[2]))" "$@"; }
close() { python3 -c "import sys; a, b, tol = map(float, sys.argv[1:]); sys.exit(abs(a - b) > tol * abs(b))" "$@"; }
render() { "$FM" render --width 16 --quality preview --progress none --wavelength 550 "$@"; }
mkdir -p "$work/r"

# two layers, the first set by the options; the sidecar lists both, bottom to top as given
render --cloud altostratus,cirrostratus --cloud-tau 4 --cloud-base 2.5 --cloud-thickness 0.8 --sun-elevation 45 \
    -o "$work/r/two.exr" && ok || fail "--cloud with two layers"
a="['atmosphere']"
[ "$(json_get "$work/r/two.json" "$a['cloud_layers']")" = 2 ] && ok || fail "two layers reported"
[ "$(json_get "$work/r/two.json" "$a['cloud_1_type']")" = altostratus ] && ok || fail "first layer's type"
close "$(json_get "$work/r/two.json" "$a['cloud_1_optical_depth_550nm']")" 4 1e-12 && ok || fail "--cloud-tau"
close "$(json_get "$work/r/two.json" "$a['cloud_1_base_km']")" 2.5 1e-12 && ok || fail "--cloud-base"
close "$(json_get "$work/r/two.json" "$a['cloud_1_thickness_km']")" 0.8 1e-12 && ok || fail "--cloud-thickness"
close "$(json_get "$work/r/two.json" "$a['cloud_2_optical_depth_550nm']")" 1 1e-12 && ok || fail "cirrostratus file's tau"
close "$(json_get "$work/r/two.json" "$a['cloud_optical_depth_550nm']")" 5 1e-12 && ok || fail "total cloud tau"
# the sun's transmittance through both: exp(-tau chord / thickness), the chords of the spherical
# shells (Earth radius 6371 km) of 2.5-3.3 km and 8-9.5 km for the sun 45 degrees up (exp(-5 / sin 45)
# but for the curvature: 0.5 % here)
expected=$(python3 -c '
import math
R, mu = 6371.0, math.sin(math.radians(45))
def chord(b, t): return math.sqrt((R + t)**2 - R * R * (1 - mu * mu)) - math.sqrt((R + b)**2 - R * R * (1 - mu * mu))
print(math.exp(-4 * chord(2.5, 3.3) / 0.8 - 1 * chord(8, 9.5) / 1.5))')
close "$(json_get "$work/r/two.json" "['sun']['cloud_direct_transmittance_550nm']")" "$expected" 1e-9 && ok ||
    fail "cloud transmittance $(json_get "$work/r/two.json" "['sun']['cloud_direct_transmittance_550nm']")"

# fog by visibility: tau = 3.912 / V x the fog file's 200 m
render --fog-visibility 100 -o "$work/r/fog.exr" && ok || fail "--fog-visibility"
close "$(json_get "$work/r/fog.json" "$a['cloud_1_optical_depth_550nm']")" 7.824 1e-12 && ok || fail "fog tau from visibility"
[ "$(json_get "$work/r/fog.json" "$a['cloud_1_base_km']")" = 0 ] && ok || fail "fog on the ground"
# liquid water path: tau = LWP C_ext / (rho <V>) (21.6 for 100 g/m^2 of stratus)
"$FM" render --cloud stratus --cloud-lwp 100 --print-atmosphere >"$work/r/lwp.json" && ok || fail "--cloud-lwp"
close "$(json_get "$work/r/lwp.json" "['cloud_optical_depth_550nm']")" 21.617 1e-3 && ok || fail "tau from LWP"

# a cloud file by path, a sky preset declaring clouds, a custom atmosphere declaring clouds
printf '{"type": "stratocumulus", "base_km": 1.2, "thickness_km": 0.4, "lwp_gm2": 60}' >"$work/deck.json"
printf '{"name": "Deck", "cloud": "%s", "sun_elevation": 30}' "$work/deck.json" >"$work/preset.json"
render --preset "$work/preset.json" -o "$work/r/p.exr" && ok || fail "preset declaring clouds"
[ "$(json_get "$work/r/p.json" "$a['cloud_1_type']")" = stratocumulus ] && ok || fail "preset's cloud file"
python3 - "$ROOT/presets/atmospheres/reference-rayleigh.json" "$work/atm.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["clouds"] = [{"type": "cirrus", "base_km": 9, "thickness_km": 1, "tau550": 0.3}]
json.dump(d, open(sys.argv[2], "w"))
PY
render --atmosphere "$work/atm.json" --cloud fog -o "$work/r/atm.exr" && ok || fail "atmosphere file with clouds"
[ "$(json_get "$work/r/atm.json" "$a['cloud_1_type']")" = cirrus ] && ok || fail "the file's layer first"
[ "$(json_get "$work/r/atm.json" "$a['cloud_2_type']")" = fog ] && ok || fail "the --cloud layer after it"

# bad input: one line naming the problem, exit 2, nothing written
expect_usage_error "unknown cloud" render --cloud stratus,nimbus -o s.exr
grep -q "unknown cloud 'nimbus' (known: altostratus, " "$work/stderr" && ok || fail "unknown cloud message: $(cat "$work/stderr")"
expect_usage_error "tau out of range" render --cloud stratus --cloud-tau 150 -o s.exr
grep -q -- "--cloud-tau: 150 is outside (0, 100]" "$work/stderr" && ok || fail "range message: $(cat "$work/stderr")"
expect_usage_error "tau without a cloud" render --cloud-tau 5 -o s.exr
expect_usage_error "tau and lwp" render --cloud stratus --cloud-tau 5 --cloud-lwp 50 -o s.exr
expect_usage_error "lwp of ice" render --cloud cirrus --cloud-lwp 50 -o s.exr
expect_usage_error "too much water" render --cloud nimbostratus --cloud-lwp 900 -o s.exr
expect_usage_error "thin layer" render --cloud stratus --cloud-thickness 0.05 -o s.exr
expect_usage_error "fog visibility" render --fog-visibility 5 -o s.exr
expect_usage_error "five layers" render --cloud fog,stratus,altostratus,cirrostratus,cirrus -o s.exr
python3 - "$ROOT/presets/atmospheres/reference-rayleigh.json" "$work/low.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["top_altitude_km"] = 5
json.dump(d, open(sys.argv[2], "w"))
PY
expect_usage_error "layer above the top" render --cloud stratus --cloud-base 4.8 --atmosphere "$work/low.json" \
    --wavelength 550 -o s.exr
grep -q "not inside the atmosphere" "$work/stderr" && ok || fail "above the top message: $(cat "$work/stderr")"
printf '{"type": "stratus", "base_km": 1, "thickness_km": 0.5, "tau550": 10, "lwp_gm2": 20}' >"$work/two.json"
expect_usage_error "cloud file with two amounts" render --cloud "$work/two.json" -o s.exr
grep -qF 'give one of "tau550", "lwp_gm2" and "visibility_m", not several' "$work/stderr" && ok ||
    fail "two amounts message: $(cat "$work/stderr")"
printf '{"type": "cumulus", "base_km": 1, "thickness_km": 0.5, "tau550": 10}' >"$work/cu.json"
expect_usage_error "unknown type in a file" render --cloud "$work/cu.json" -o s.exr
grep -qF '$.type: "cumulus" is not a cloud type' "$work/stderr" && ok || fail "type message: $(cat "$work/stderr")"

echo "$checks checks passed, $failures failed"
[ "$failures" -eq 0 ]

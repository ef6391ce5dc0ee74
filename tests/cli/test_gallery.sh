#!/usr/bin/env bash
# The gallery (docs/gallery/), without rendering it (docs/gallery/render takes minutes): the
# script refuses bad arguments with exit 2, one line and nothing created; the committed README.md
# links every image there and nothing else, one per biome and per frame of the day; every image is
# an 8-bit PNG of the size its caption states; and the README's commands carry the script's
# exposure and time series, so a script changed without re-rendering fails here.
# Usage: test_gallery.sh
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
G=$ROOT/docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0 checks=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { checks=$((checks + 1)); }

# --- bad arguments: exit 2, one "docs/gallery/render:" line, no folder made ----------------------
refused() {
    local what=$1
    shift
    "$G/render" "$@" >"$work/stdout" 2>"$work/stderr"
    local rc=$?
    [ $rc -eq 2 ] && ok || fail "$what: exit $rc, expected 2"
    if [ "$(wc -l <"$work/stderr")" -eq 1 ] && grep -q '^docs/gallery/render: ' "$work/stderr"; then ok
    else fail "$what: expected one 'docs/gallery/render:' line, got: $(cat "$work/stderr")"; fi
    [ ! -e "$work/new" ] && ok || fail "$what: created $work/new"
}
refused "--threads not a number" --threads many --out "$work/new"
refused "--threads out of range" --threads 257 --out "$work/new"
refused "--threads without a value" --out "$work/new" --threads
refused "unknown argument" --out "$work/new" --fast
refused "--quick without --out (would replace the committed gallery)" --quick
grep -q "would replace the committed gallery" "$work/stderr" && ok || fail "--quick message: $(cat "$work/stderr")"
touch "$work/file"
refused "--out is a file" --out "$work/file/sub"

# --- the committed gallery ----------------------------------------------------------------------
readme=$G/README.md
[ -f "$readme" ] && ok || { echo "FAIL: $readme missing"; exit 1; }
grep -o '](\([^)]*\.png\))' "$readme" | sed 's/^](//; s/)$//' | sort -u >"$work/linked"
(cd "$G" && find . -name '*.png' | sed 's|^\./||' | sort) >"$work/present"
missing=$(comm -23 "$work/linked" "$work/present")
orphans=$(comm -13 "$work/linked" "$work/present")
[ -z "$missing" ] && ok || fail "README.md links missing images: $missing"
[ -z "$orphans" ] && ok || fail "images not in README.md: $orphans"
for b in "$ROOT"/presets/biomes/*.json; do
    name=$(basename "$b" .json)
    grep -qx "biomes/$name.png" "$work/linked" && ok || fail "no image of the biome $name"
done
frames=$(grep -c '^day/paris-[0-9]\{4\}\.png$' "$work/linked")
[ "$frames" -eq 12 ] && ok || fail "the day has $frames frames, expected 12"

# PNG header: 8-bit depth, colour type RGB (2) or RGBA (6), and the size the README states
while read -r img; do
    read -r w h depth ctype < <(od -An -tu1 -j16 -N10 "$G/$img" |
        awk '{ print $1*16777216 + $2*65536 + $3*256 + $4, $5*16777216 + $6*65536 + $7*256 + $8, $9, $10 }')
    { [ "$depth" = 8 ] && { [ "$ctype" = 2 ] || [ "$ctype" = 6 ]; }; } && ok ||
        fail "$img: bit depth $depth, colour type $ctype (expected 8-bit RGB)"
    case $img in day.png) continue ;; esac  # the contact sheet has no caption of its own
    grep -q "$w x $h" "$readme" && ok || fail "$img is $w x $h, which README.md does not state"
done <"$work/present"

# the README was written by the current script: its commands carry the script's settings
script_value() { sed -n "s/^$1=\([^ ]*\).*/\1/p" "$G/render"; }
ev=$(script_value SUNSET_EV)
grep -q -- "--exposure $ev\$" "$readme" && ok || fail "README.md's sunset exposure is not the script's ($ev)"
start=$(sed -n 's/^DAY_START=\([0-9:]*\) DAY_STEP=\([0-9]*\).*/\1/p' "$G/render")
step=$(sed -n 's/^DAY_START=\([0-9:]*\) DAY_STEP=\([0-9]*\).*/\2/p' "$G/render")
[ -n "$start" ] && [ -n "$step" ] && ok || fail "cannot read DAY_START / DAY_STEP from the script"
grep -q -- "--time-start $start .* --step $step " "$readme" && ok ||
    fail "README.md's day series is not the script's ($start every $step min)"

echo "$checks checks passed, $failures failed"
[ $failures -eq 0 ]

#!/usr/bin/env bash
# A copied executable finds its presets (biomes, skies, the OpenColorIO config) beside itself, in
# the order docs/packaging.md gives: $FIRMAMENT_PRESETS, EXE_DIR/presets, EXE_DIR/../presets,
# EXE_DIR/../share/firmament/presets, then the source tree.  A biome that only the copied presets hold tells which folder was used.  (With no
# presets anywhere, the portable build's one error line: tests/package/bare_root.sh.)
# Usage: test_relocated.sh path/to/firmament
set -u
FM=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
source_presets=$(cd "$here/../../presets" && pwd)
. "$here/harness.sh"

# layout A: firmament and presets/ in one folder; B: bin/firmament and presets/ (the zip's);
# C: bin/firmament and share/firmament/presets/ (cmake --install)
mkdir -p "$work/a" "$work/b/bin" "$work/c/bin" "$work/c/share/firmament"
cp "$FM" "$work/a/firmament"
cp "$FM" "$work/b/bin/firmament"
cp "$FM" "$work/c/bin/firmament"
cp -r "$source_presets" "$work/a/presets"
sed 's/"name": "rural"/"name": "copied-only"/' "$source_presets/biomes/rural.json" >"$work/a/presets/biomes/copied-only.json"
cp -r "$work/a/presets" "$work/b/presets"
cp -r "$work/a/presets" "$work/c/share/firmament/presets"
args=(render --biome copied-only --width 16 --quality preview --progress none)

for exe in "$work/a/firmament" "$work/b/bin/firmament" "$work/c/bin/firmament"; do
    rm -rf "$work/out" && mkdir -p "$work/out"
    if (cd "$work/out" && env -u FIRMAMENT_PRESETS -u OCIO "$exe" "${args[@]}" -o sky.exr 2>"$work/stderr"); then ok; else
        fail "$exe: the presets beside it were not used: $(cat "$work/stderr")"
    fi
    [ -s "$work/out/sky.exr" ] && ok || fail "$exe: no map written"
done
# the presets beside it are not consulted once the copy's folder loses them (the source tree is)
mv "$work/a/presets" "$work/a/elsewhere"
rm -rf "$work/out" && mkdir -p "$work/out"
(cd "$work/out" && env -u FIRMAMENT_PRESETS -u OCIO "$work/a/firmament" "${args[@]}" -o sky.exr >/dev/null 2>&1) &&
    fail "copied-only found without presets beside the executable" || ok
# $FIRMAMENT_PRESETS comes first
rm -rf "$work/out" && mkdir -p "$work/out"
(cd "$work/out" && FIRMAMENT_PRESETS="$work/a/elsewhere" "$work/a/firmament" "${args[@]}" -o sky.exr 2>"$work/stderr") &&
    ok || fail "FIRMAMENT_PRESETS not used: $(cat "$work/stderr")"
rm -rf "$work/out" && mkdir -p "$work/out"
(cd "$work/out" && FIRMAMENT_PRESETS="$source_presets" "$work/b/bin/firmament" "${args[@]}" -o sky.exr >/dev/null 2>&1) &&
    fail "FIRMAMENT_PRESETS did not override the presets beside the executable" || ok

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]

#!/usr/bin/env bash
# The Windows extension zip's firmament.exe, run by Debian's Wine, against this machine's Linux
# build: the default sky and a time series equal within 1e-4 relative RMS (same seed; they differ
# by the C libraries' sin/exp/pow and the compiled-in colour spaces' double precision against
# OpenColorIO's float), the sidecar's numbers within 1e-6, `firmament sun` within its printed
# digits, --list-colorspaces the same and $OCIO naming another config refused, bad input (exit 2,
# one line, nothing written), an existing output kept when a render fails and replaced when one
# succeeds, a UTF-8 file name, Windows path separators, --threads, JSON progress, and Ctrl-C (Wine
# delivers SIGINT as a console control event: exit 130, no temporary file left); the zip is
# unpacked in a folder whose name has spaces and non-ASCII letters.
# Usage: wine.sh ZIP LINUX_FIRMAMENT WORK_DIR   (the Wine prefix is made once in WORK_DIR/wineprefix)
set -euo pipefail
zip=$(realpath "$1")
linux=$(realpath "$2")
mkdir -p "$3"
work=$(realpath "$3")
command -v wine >/dev/null || { echo "FAIL: wine is not installed (scripts/test-package installs Debian's wine and wine64)"; exit 1; }
export WINEPREFIX=$work/wineprefix WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml=" # no Mono/Gecko
failures=0
fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}

run="$work/run é 空" # the package in a folder whose name is not ASCII and has spaces
rm -rf "$run"
mkdir -p "$run/win" "$run/lin"
python3 -c 'import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extractall(sys.argv[2])' "$zip" "$run"
exe=$run/firmament_sky/bin/firmament.exe
[ -f "$exe" ] || { echo "FAIL: $zip holds no firmament_sky/bin/firmament.exe"; exit 1; }
win() { wine "$exe" "$@"; }

version=$(win --version 2>&1 | tr -d '\r') || true
case "$version" in *windows-x64*) ;; *) echo "FAIL: firmament.exe --version: '$version'"; exit 1 ;; esac
echo "$version"

# compare A B: relative RMS of B against A (firmament compare --json), checked against 1e-4
compare() {
    local rms
    rms=$("$linux" compare "$1" "$2" --json | python3 -c 'import json, sys; print(json.load(sys.stdin)["rms"])')
    echo "  $(basename "$1"): relative RMS $rms"
    python3 -c "import sys; sys.exit(0 if float('$rms') < 1e-4 else 1)" || fail "$(basename "$1"): relative RMS $rms >= 1e-4"
}

# The default sky (a smaller map, for time) and its sidecar.
(cd "$run/win" && win render --width 256 --seed 3 -o sky.exr) || fail "render (Wine) failed"
(cd "$run/lin" && "$linux" render --width 256 --seed 3 -o sky.exr) || fail "render (Linux) failed"
compare "$run/lin/sky.exr" "$run/win/sky.exr"
python3 - "$run/lin/sky.json" "$run/win/sky.json" <<'PY' || fail "sidecars differ"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
bad = []
def walk(x, y, where):
    if isinstance(x, dict):
        if set(x) != set(y):
            bad.append(f"{where}: keys {sorted(set(x) ^ set(y))}")
        for k in set(x) & set(y):
            walk(x[k], y[k], f"{where}.{k}")
    elif isinstance(x, list):
        if len(x) != len(y):
            bad.append(f"{where}: lengths {len(x)} {len(y)}")
        for i, (u, v) in enumerate(zip(x, y)):
            walk(u, v, f"{where}[{i}]")
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        scale = max(abs(x), abs(y), 1e-9 if "direction" not in where else 1.0)
        if abs(x - y) > 1e-6 * scale:
            bad.append(f"{where}: {x} vs {y}")
    elif x != y:
        bad.append(f"{where}: {x!r} vs {y!r}")
walk(a, b, "sidecar")
for line in bad:
    print("  ", line)
sys.exit(1 if bad else 0)
PY

# A time series: three maps and sidecars, each as on Linux.
series=(render --date 2023-06-21 --time-start 06:00 --time-end 18:00 --step 360 --utc-offset +02:00
        --latitude 48.8566 --longitude 2.3522 --width 128 --seed 5 -o day.exr)
(cd "$run/win" && win "${series[@]}" >/dev/null) || fail "time series (Wine) failed"
(cd "$run/lin" && "$linux" "${series[@]}" >/dev/null) || fail "time series (Linux) failed"
for i in 0000 0001 0002; do
    [ -f "$run/win/day_$i.json" ] || fail "day_$i.json missing"
    compare "$run/lin/day_$i.exr" "$run/win/day_$i.exr"
done

# firmament sun: the same fields, the numbers equal to the digits printed.
sun=(sun --date 2023-06-21 --time 12:00 --utc-offset +02:00 --latitude 48.8566 --longitude 2.3522 --json)
python3 - "$("$linux" "${sun[@]}")" "$(win "${sun[@]}" | tr -d '\r')" <<'PY' || fail "firmament sun differs"
import json, sys
a, b = (json.loads(s) for s in sys.argv[1:3])
bad = [k for k in a if k not in b or (a[k] != b[k] and not (isinstance(a[k], float) and abs(a[k] - b[k]) <= 1e-6 * max(1, abs(a[k]))))]
print("  sun: %d fields, %s" % (len(a), "equal" if not bad else "differ in " + ", ".join(bad)))
sys.exit(1 if bad or set(a) != set(b) else 0)
PY
[ "$(win render --list-colorspaces | tr -d '\r')" = "$("$linux" render --list-colorspaces)" ] ||
    fail "--list-colorspaces differs from the Linux build's"
# another OpenColorIO config cannot be used without OpenColorIO: one line, exit 2
set +e
OCIO="$run/firmament_sky/presets/skies/golden-hour.json" win render --width 64 -o "$run/ocio.exr" 2>"$run/ocio.err"
code=$?
set -e
[ "$code" -eq 2 ] && [ "$(wc -l <"$run/ocio.err")" -eq 1 ] && grep -q "no OpenColorIO" "$run/ocio.err" ||
    fail "\$OCIO naming another config: exit $code, $(cat "$run/ocio.err")"

# Bad input: exit 2, one line on stderr, nothing written.
set +e
(cd "$run/win" && win render --sun-elevation 95 -o bad.exr 2>"$run/bad.err")
code=$?
set -e
[ "$code" -eq 2 ] || fail "bad input: exit $code, expected 2"
[ "$(wc -l <"$run/bad.err")" -eq 1 ] && grep -q "sun-elevation" "$run/bad.err" ||
    fail "bad input: stderr is not one line naming --sun-elevation: $(cat "$run/bad.err")"
[ ! -e "$run/win/bad.exr" ] || fail "bad input wrote bad.exr"

# An existing output is kept when the render fails after it started (half floats cannot hold the
# sun disk), and replaced (MoveFileExW) when a render succeeds.
echo "old map" >"$run/win/keep.exr"
echo "old sidecar" >"$run/win/keep.json"
set +e
(cd "$run/win" && win render --width 256 --quality preview --half -o keep.exr 2>/dev/null)
code=$?
set -e
[ "$code" -ne 0 ] || fail "a --half render with the sun disk succeeded"
[ "$(cat "$run/win/keep.exr")" = "old map" ] && [ "$(cat "$run/win/keep.json")" = "old sidecar" ] ||
    fail "the existing keep.exr/keep.json changed after a failed render"
(cd "$run/win" && win render --width 64 -o keep.exr) || fail "render over an existing file failed"
[ "$(head -c 4 "$run/win/keep.exr" | od -An -tx1 | tr -d ' ')" = "762f3101" ] ||
    fail "keep.exr was not replaced by an EXR"

# A UTF-8 file name, and backslashes as separators (the sidecar goes beside the map).
name="ciel-été-天空.exr"
(cd "$run/win" && win render --width 64 -o "$name") || fail "render to $name failed"
[ -f "$run/win/$name" ] && [ -f "$run/win/${name%.exr}.json" ] || fail "$name or its sidecar missing: $(ls "$run/win")"
mkdir -p "$run/win/sub"
(cd "$run/win" && win render --width 64 -o 'sub\map.exr') || fail "render to sub\\map.exr failed"
[ -f "$run/win/sub/map.exr" ] && [ -f "$run/win/sub/map.json" ] || fail "sub\\map.exr or sub\\map.json missing"

# --threads: one thread and three give the same map (the work is split, not the random numbers).
(cd "$run/win" && win render --width 128 --seed 2 --threads 1 -o t1.exr && win render --width 128 --seed 2 --threads 3 -o t3.exr) ||
    fail "--threads renders failed"
rms=$("$linux" compare "$run/win/t1.exr" "$run/win/t3.exr" --json | python3 -c 'import json, sys; print(json.load(sys.stdin)["rms"])')
[ "$rms" = "0" ] || fail "--threads 1 and 3 differ: relative RMS $rms"

# Progress as JSON lines on stdout, ending with the done event.
(cd "$run/win" && win render --width 64 --progress json -o prog.exr | tr -d '\r' >"$run/progress.txt") || fail "progress render failed"
grep -q '^{"event": "progress", "fraction": ' "$run/progress.txt" && tail -n 1 "$run/progress.txt" | grep -q '^{"event": "done"' ||
    fail "no JSON progress: $(head -c 300 "$run/progress.txt")"

# Ctrl-C: stops the render, exit 130, no temporary file left beside the output.
(cd "$run/win" && exec wine "$exe" render --width 1024 --quality final --progress json -o int.exr >"$run/int.out" 2>"$run/int.err") &
pid=$!
for _ in $(seq 1 300); do grep -q multiple "$run/int.out" 2>/dev/null && break; sleep 0.1; done
kill -INT "$pid"
set +e
wait "$pid"
code=$?
set -e
[ "$code" -eq 130 ] || fail "Ctrl-C: exit $code, expected 130 ($(cat "$run/int.err"))"
grep -q "interrupted" "$run/int.err" || fail "Ctrl-C: no 'interrupted' message: $(cat "$run/int.err")"
leftover=$(cd "$run/win" && ls -A | grep -E '^\.|^int\.' || true)
[ -z "$leftover" ] || fail "Ctrl-C left files: $leftover"

echo "wine.sh: $failures failure(s)"
[ "$failures" -eq 0 ]

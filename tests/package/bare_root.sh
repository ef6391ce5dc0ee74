#!/usr/bin/env bash
# The Linux extension zip on a bare Debian 12: a minimal root (debootstrap --variant=minbase
# bookworm: no -dev packages, none of firmament's libraries) gets the zip's firmament_sky/ folder,
# and the bundled executable renders there (chroot) the same map as this machine's normal build
# (same seed: within 1e-5 relative, and says whether bit for bit).  Also: a copy of the executable
# and its lib/ without presets fails with one line naming where it looked; $FIRMAMENT_PRESETS or a
# presets/ beside the copy make it render.
# Usage: bare_root.sh ZIP REFERENCE_FIRMAMENT CACHE_DIR   (root: debootstrap, chroot and mount)
# The root is built once into CACHE_DIR/debian-bookworm-minbase and reused.
set -euo pipefail
zip=$(realpath "$1")
reference=$(realpath "$2")
cache=$3
if [ "$(id -u)" -ne 0 ]; then
    echo "FAIL: bare_root.sh needs root (debootstrap, chroot, mount); run scripts/test-package as root" >&2
    exit 1
fi
for tool in debootstrap unshare chroot; do
    command -v "$tool" >/dev/null || { echo "FAIL: $tool is not installed (scripts/test-package installs it)" >&2; exit 1; }
done
mkdir -p "$cache"
cache=$(realpath "$cache")
root=$cache/debian-bookworm-minbase
if [ ! -e "$root/.complete" ]; then
    # Debian's packages from the mirror apt uses here when it is a Debian one, else Debian's own
    mirror=$(grep -hE '^[[:space:]]*(URIs:|deb )' /etc/apt/sources.list /etc/apt/sources.list.d/*.sources \
        /etc/apt/sources.list.d/*.list 2>/dev/null | grep -oE 'https?://[^ ]*/debian/?' | grep -v -- '-security' |
        head -n1 || true) # entries only: a comment may name a snapshot URL that is no mirror
    mirror=${mirror:-http://deb.debian.org/debian}
    rm -rf "$root.partial"
    start=$(date +%s)
    if ! debootstrap --variant=minbase bookworm "$root.partial" "$mirror" >"$cache/debootstrap.log" 2>&1; then
        tail -n 20 "$cache/debootstrap.log"
        echo "FAIL: debootstrap bookworm from $mirror failed (log: $cache/debootstrap.log)"
        exit 1
    fi
    mv "$root.partial" "$root"
    touch "$root/.complete"
    echo "debootstrap (minbase bookworm from $mirror): $(($(date +%s) - start)) s, $(du -sm "$root" | cut -f1) MB"
fi

failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# in_root CMD...: runs CMD in the root with an empty environment and the root's own /proc (ld.so's
# $ORIGIN and the executable's own location come from /proc/self/exe); the mount ends with it.
in_root() {
    unshare --mount --fork -- sh -c 'mount -t proc proc "$0/proc" && exec chroot "$0" env -i PATH=/usr/bin:/bin "$@"' \
        "$root" "$@"
}

ls "$root"/usr/lib/x86_64-linux-gnu/ | grep -qiE 'OpenColorIO|OpenEXR|Imath|cjson|png16|yaml-cpp|expat' &&
    fail "the root is not bare: $(ls "$root"/usr/lib/x86_64-linux-gnu/ | grep -iE 'OpenColorIO|OpenEXR|Imath|cjson|png16|yaml-cpp|expat' | tr '\n' ' ')"
rm -rf "$root/opt/fm" "$root/tmp/fm"
mkdir -p "$root/opt/fm" "$root/tmp/fm"
trap 'rm -rf "$root/opt/fm" "$root/tmp/fm"' EXIT
# unzipped as Blender does, modes kept (the add-on restores a lost executable bit itself)
python3 - "$zip" "$root/opt/fm" <<'PY'
import os, sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as z:
    for info in z.infolist():
        path = z.extract(info, sys.argv[2])
        if info.external_attr >> 16:
            os.chmod(path, (info.external_attr >> 16) & 0o777)
PY
exe=/opt/fm/firmament_sky/bin/firmament

version=$(in_root "$exe" --version 2>&1) || true
echo "in the root: $version"
cmake_version=$(sed -n 's/^project(firmament VERSION \([0-9.]*\) .*/\1/p' "$(dirname "$0")/../../CMakeLists.txt")
[[ "$version" =~ ^firmament\ ${cmake_version//./\\.}\ \(([0-9a-f]{7}(-dirty)?|unknown),\ release,\ linux-x64\)$ ]] ||
    fail "--version in the root: '$version', expected 'firmament $cmake_version (REVISION, release, linux-x64)'"

# the same map: a biome (presets/biomes), a colour space (the OpenColorIO config), a fixed seed
args=(render --biome urban --sun-elevation 8 --colorspace ACEScg --width 64 --quality preview --seed 7 --threads 2
      --progress none)
start=$(date +%s%N)
in_root "$exe" "${args[@]}" -o /tmp/fm/sky.exr || fail "render in the root failed"
echo "render in the root: $((($(date +%s%N) - start) / 1000000)) ms"
"$reference" "${args[@]}" -o "$cache/reference.exr" || fail "reference render failed"
if [ -s "$root/tmp/fm/sky.exr" ]; then
    diff=$("$reference" compare "$root/tmp/fm/sky.exr" "$cache/reference.exr" --json)
    python3 -c 'import json, sys; d = json.loads(sys.argv[1]); sys.exit(0 if d["max"] <= 1e-5 else 1)' "$diff" ||
        fail "the root's map differs from the normal build's by more than 1e-5 relative: $diff"
    python3 -c 'import json, sys; print("identical pixels" if json.loads(sys.argv[1])["max"] == 0 else "within 1e-5")' "$diff"
else
    fail "no map written in the root"
fi

# a copy of the executable and its libraries alone: one line, exit 2, naming where it looked
mkdir -p "$root/opt/fm/copy"
cp -r "$root/opt/fm/firmament_sky/bin/." "$root/opt/fm/copy/"
set +e
in_root /opt/fm/copy/firmament render --width 16 --quality preview -o /tmp/fm/none.exr >"$cache/stdout" 2>"$cache/stderr"
rc=$?
set -e
[ $rc -eq 2 ] || fail "no presets: exit $rc, expected 2"
[ "$(wc -l <"$cache/stderr")" -eq 1 ] && grep -q "^firmament: firmament's presets were not found (.*'/opt/fm/copy'" "$cache/stderr" ||
    fail "no presets: expected one line naming /opt/fm/copy, got: $(cat "$cache/stderr")"
echo "no presets: $(cat "$cache/stderr")"
[ ! -e "$root/tmp/fm/none.exr" ] || fail "no presets: a map was written"
in_root env FIRMAMENT_PRESETS=/opt/fm/firmament_sky/presets /opt/fm/copy/firmament render --width 16 --quality preview \
    --progress none -o /tmp/fm/env.exr || fail "FIRMAMENT_PRESETS: no render"
cp -r "$root/opt/fm/firmament_sky/presets" "$root/opt/fm/copy/presets"
in_root /opt/fm/copy/firmament render --width 16 --quality preview --progress none -o /tmp/fm/beside.exr ||
    fail "presets beside the copy: no render"

[ "$failures" -eq 0 ] && echo "bare Debian 12 root: all checks passed"
[ "$failures" -eq 0 ]

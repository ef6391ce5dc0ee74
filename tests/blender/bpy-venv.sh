#!/usr/bin/env bash
# Prints the python of a venv holding PyPI's bpy VERSION.* (e.g. 4.2), creating it on first use under
# $FIRMAMENT_BPY_CACHE (default ~/.cache/firmament-bpy; pip's own cache keeps the wheel).  The venv is
# made once (under a lock: tests run in parallel) and marked complete only when `import bpy` works.
# Exits 77 with one line when this version cannot be installed here (CTest skips that test only).
set -u
version=$1
cache=${FIRMAMENT_BPY_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/firmament-bpy}
venv=$cache/bpy$version
mkdir -p "$cache" || { echo "SKIP: bpy $version: cannot create $cache"; exit 77; }
exec 9>"$cache/bpy$version.lock"
flock 9
if [ ! -f "$venv/.complete" ]; then
    rm -rf "$venv"
    log=$cache/bpy$version.log
    if ! { python3 -m venv "$venv" && "$venv/bin/pip" install "bpy==$version.*" \
           && "$venv/bin/python" -c "import bpy; print(bpy.app.version_string)"; } >"$log" 2>&1; then
        echo "SKIP: bpy $version cannot be installed here (python3 -m venv; pip install 'bpy==$version.*'): $(tail -n 1 "$log")" >&2
        rm -rf "$venv"
        exit 77
    fi
    touch "$venv/.complete"
fi
echo "$venv/bin/python"

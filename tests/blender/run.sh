#!/usr/bin/env bash
# Runs one Blender test script headless with an isolated user profile (everything under a temporary
# HOME; nothing touches the real ~/.config/blender).
#   VERSION 3.4: Debian's blender executable (-b --factory-startup --python-exit-code 1, so that an
#                uncaught exception fails the test: without it Blender exits 0).
#   VERSION 4.2, 4.5, 5.0: PyPI's bpy wheel (a real Blender build as a Python module) in a venv that
#                bpy-venv.sh creates once and caches; the script runs under the venv's python.
# A Blender that cannot be installed here exits 77 (CTest's skip) with one line saying why.
# Usage: run.sh VERSION SCRIPT.py ADDON.zip FIRMAMENT_EXECUTABLE
set -u
version=$1 script=$2 zip=$3 exe=$4
here=$(cd "$(dirname "$0")" && pwd)
if [ "$version" = 3.4 ]; then
    command -v blender >/dev/null || { echo "SKIP: Debian's blender is not installed (apt-get install blender)"; exit 77; }
    run=(blender -b --factory-startup --python-exit-code 1 -P "$script" --)
else
    py=$("$here/bpy-venv.sh" "$version") || exit $?
    run=("$py" "$script" --)
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/out"
# the test zip: the built one, with the executable bundled as bin/firmament when the build did not
zip=$("$here/bundle-zip.sh" "$zip" "$exe" "$work/firmament_sky.zip") || exit 1
BLENDER_USER_RESOURCES="$work/user" BLENDER_USER_SCRIPTS="$work/scripts" BLENDER_USER_CONFIG="$work/config" \
    BLENDER_USER_DATAFILES="$work/datafiles" HOME="$work" XDG_CACHE_HOME="$work/cache" TMPDIR="$work" FIRMAMENT_BLENDER="$version" \
    FIRMAMENT_TEST_KEEP="${FIRMAMENT_TEST_KEEP:-}" FIRMAMENT_EXECUTABLE= \
    "${run[@]}" "$zip" "$exe" "$work/out"
rc=$?
if [ -n "${FIRMAMENT_TEST_KEEP:-}" ]; then mkdir -p "$FIRMAMENT_TEST_KEEP" && cp -r "$work/out/." "$FIRMAMENT_TEST_KEEP/"; fi
exit $rc

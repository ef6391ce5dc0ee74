#!/usr/bin/env bash
# Runs one Blender test script headless with Debian's real blender, an isolated user profile
# (BLENDER_USER_SCRIPTS in a temporary folder) and --python-exit-code 1, so that an uncaught
# exception fails the test (without it Blender exits 0).
# Usage: run.sh SCRIPT.py ADDON.zip FIRMAMENT_EXECUTABLE
set -u
script=$1 zip=$2 exe=$3
command -v blender >/dev/null || { echo "blender is not installed (scripts/test installs it)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/scripts" "$work/out"
# the add-on's cache lives under the user profile too: nothing touches the real ~/.config/blender
BLENDER_USER_SCRIPTS="$work/scripts" BLENDER_USER_CONFIG="$work/config" BLENDER_USER_DATAFILES="$work/datafiles" \
    HOME="$work" FIRMAMENT_TEST_KEEP="${FIRMAMENT_TEST_KEEP:-}" \
    blender -b --factory-startup --python-exit-code 1 -P "$script" -- "$zip" "$exe" "$work/out"
rc=$?
if [ -n "${FIRMAMENT_TEST_KEEP:-}" ]; then mkdir -p "$FIRMAMENT_TEST_KEEP" && cp -r "$work/out/." "$FIRMAMENT_TEST_KEEP/"; fi
exit $rc

#!/usr/bin/env bash
# Runs a Blender test script in a real window on a virtual X display (Xvfb, Mesa's software
# OpenGL), so that modal operators, timers and simulated key presses work; an isolated user
# profile as in run.sh.  The script sets the exit status itself (os._exit).
# Usage: run_window.sh SCRIPT.py ADDON.zip FIRMAMENT_EXECUTABLE [ARGS...] (after OUT in the script's argv)
set -u
script=$1 zip=$2 exe=$3
shift 3
command -v blender >/dev/null || { echo "blender is not installed (scripts/test installs it)"; exit 1; }
command -v xvfb-run >/dev/null || { echo "xvfb-run is not installed (scripts/test installs xvfb)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/scripts" "$work/out"
zip=$("$(dirname "$0")/bundle-zip.sh" "$zip" "$exe" "$work/firmament_sky.zip") || exit 1
BLENDER_USER_SCRIPTS="$work/scripts" BLENDER_USER_CONFIG="$work/config" BLENDER_USER_DATAFILES="$work/datafiles" \
    HOME="$work" XDG_CACHE_HOME="$work/cache" FIRMAMENT_EXECUTABLE= timeout 300 xvfb-run -a -s "-screen 0 1280x800x24" \
    blender --factory-startup --enable-event-simulate --python-exit-code 1 -P "$script" -- "$zip" "$exe" "$work/out" "$@"

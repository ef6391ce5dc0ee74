#!/usr/bin/env bash
# Validates the built zip's blender_manifest.toml with Blender's own strict checker (the extension
# command line's `validate`: keys, tagline and permission lengths, tags), taken from bpy VERSION.
# Usage: validate-manifest.sh VERSION ADDON.zip
set -u
version=$1 zip=$2
py=$("$(dirname "$0")/bpy-venv.sh" "$version") || exit $?
root=$("$py" -c "import importlib.util, os; print(os.path.dirname(importlib.util.find_spec('bpy').origin))")
cli=$root/$version/scripts/addons_core/bl_pkg/cli/blender_ext.py
[ -f "$cli" ] || { echo "no blender_ext.py in bpy $version ($cli)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 -c "import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extractall(sys.argv[2])" "$zip" "$work" || exit 1
out=$("$py" "$cli" validate "$work/firmament_sky" 2>&1)
echo "$out"
case "$out" in *invalid*|*rror*) exit 1 ;; esac

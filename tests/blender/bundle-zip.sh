#!/usr/bin/env bash
# Prints the zip the tests install: ZIP itself when it bundles the executable (firmament_sky/bin/
# firmament), else a copy at OUT with EXE added there, so that the add-on is always tested finding
# its bundled executable with no preference set.
# Usage: bundle-zip.sh ZIP EXE OUT
set -eu
python3 - "$@" <<'PY'
import shutil, sys, zipfile
src, exe, out = sys.argv[1:4]
with zipfile.ZipFile(src) as z:
    if "firmament_sky/bin/firmament" in z.namelist():
        print(src)
        sys.exit(0)
shutil.copyfile(src, out)
with zipfile.ZipFile(out, "a", zipfile.ZIP_DEFLATED) as z:
    z.write(exe, "firmament_sky/bin/firmament")
print(out)
PY

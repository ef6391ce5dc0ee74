#!/usr/bin/env python3
"""The add-on's bpy-free runner (blender_addon/firmament_sky/runner.py, command.py, options.py)
driving the Windows zip's firmament.exe under Wine, as the add-on does on Windows: the executable's
name in the zip, its options table (`firmament.exe options --json`), an argument list (no shell)
with spaces, an apostrophe, & and % and non-ASCII characters in the paths, JSON progress read from
the .exe's stdout (CRLF line ends), the done event and the files; a failure
(one line, outputs removed); a cancel (state, outputs removed).  The Windows branch of cancel
(Ctrl-Break to the child's process group) needs a Windows Python and is not run here: under Wine
the runner is a Linux process and cancels with SIGTERM, which Wine turns into TerminateProcess.
Usage: wine_runner.py ZIP LINUX_FIRMAMENT WORK_DIR"""
import json
import os
import shutil
import subprocess
import sys
import time
import types
import zipfile

zip_path, linux, work = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3])
source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# The add-on's bpy-free modules, as the package firmament_sky without its __init__ (which needs bpy).
package = types.ModuleType("firmament_sky")
package.__path__ = [os.path.join(source, "blender_addon", "firmament_sky")]
sys.modules["firmament_sky"] = package
from firmament_sky import command, options, runner  # noqa: E402

os.environ.update(WINEPREFIX=os.path.join(work, "wineprefix"), WINEDEBUG="-all", WINEDLLOVERRIDES="mscoree,mshtml=")
failures = []


def check(cond, what):
    print(("ok: " if cond else "FAIL: ") + what)
    if not cond:
        failures.append(what)


run = os.path.join(work, "runner")
shutil.rmtree(run, ignore_errors=True)
os.makedirs(run)
zipfile.ZipFile(zip_path).extractall(run)
exe = os.path.join(run, "firmament_sky", "bin", runner.executable_name("nt"))
check(os.path.isfile(exe), "the add-on's Windows executable name %s is in the zip" % runner.executable_name("nt"))
if not os.path.isfile(exe):
    sys.exit(1)

settings = {
    "latitude": 48.8566, "longitude": 2.3522, "sun_elevation": 12.0, "sun_azimuth": 250.0, "turbidity": 1.0,
    "aod550": 0.1, "humidity": 50.0, "ozone_du": 300.0, "albedo": 0.2, "altitude": 0.0, "utc_offset": 2.0,
    "biome": "rural", "quality": "preview", "sun_mode": "LAMP", "resolution": 128, "year": 2023, "month": 6,
    "day": 21, "hour": 20, "minute": 30, "second": 0, "threads": 2, "sun_source": "TIME",
    "aerosol_amount": "TURBIDITY", "use_humidity": False, "ozone_mode": "AUTO",
}
# Paths as a Windows user's may be: spaces, an apostrophe, a shell's special characters, non-ASCII;
# passed as a list (a double quote cannot be in a Windows file name).
folder = os.path.join(run, "Mes cartes (ciel & nuit) 100% d'été")
os.makedirs(folder)
output, sidecar = os.path.join(folder, "ciel du soir.exr"), os.path.join(folder, "ciel du soir.json")
# The add-on runs the executable it found; on Linux a Windows program runs through wine, so it is
# given a two-line launcher (exec: the runner's signals reach Wine).  The options table comes from
# the .exe itself (firmament.exe options --json).
launcher = os.path.join(run, "firmament-wine")
with open(launcher, "w") as f:
    f.write('#!/bin/sh\nexec wine "%s" "$@"\n' % exe)
os.chmod(launcher, 0o755)
opts = options.load(launcher)
check("--biome" in opts and "rural" in options.choices(opts, "--biome"), "the options table read from the .exe")
args = command.build_arguments(launcher, opts, settings, output, sidecar)
r = runner.Runner(args, outputs=[output, sidecar]).start()
fractions = []
state = r.wait(on_progress=lambda f, stage: fractions.append(f), interval=0.05)
check(state == runner.Runner.DONE, "render through the runner: %s (%s)" % (state, r.error_text() if state != "done" else ""))
check(r.done_event is not None and r.done_event.get("output", "").endswith("ciel du soir.exr"),
      "the done event names the output: %s" % (r.done_event,))
check(len(fractions) >= 2 and fractions == sorted(fractions), "progress read and increasing (%d updates)" % len(fractions))
check(os.path.isfile(output) and os.path.isfile(sidecar), "the map and sidecar are where the runner said")
if os.path.isfile(sidecar):
    sun = json.load(open(sidecar))["sun"]
    spa = json.loads(subprocess.run([linux, "sun", "--date", "2023-06-21", "--time", "20:30", "--utc-offset", "+02:00",
                                     "--latitude", "48.8566", "--longitude", "2.3522", "--json"],
                                    capture_output=True, text=True, check=True).stdout)
    check(abs(sun["elevation_deg"] - spa["elevation_deg"]) < 1e-4,
          "the sidecar's sun %.4f deg is the Linux build's for the time given: %.4f deg"
          % (sun["elevation_deg"], spa["elevation_deg"]))

# A failure: a value the add-on's own check would refuse, given straight to the executable.
bad = list(args)
bad[bad.index("--albedo") + 1] = "2.5"
r = runner.Runner(bad, outputs=[output, sidecar]).start()
check(r.wait() == runner.Runner.FAILED and r.returncode == 2, "bad albedo fails with exit 2: %s" % r.returncode)
check(len(r.stderr_lines) == 1 and "albedo" in r.error_text(), "one line naming albedo: %r" % r.stderr_lines)
check(not os.path.exists(output) and not os.path.exists(sidecar), "the failed run's outputs were removed")

# A cancel while it renders a larger map.
big = list(args)
big[big.index("--width") + 1] = "1024"
big[big.index("--quality") + 1] = "final"
r = runner.Runner(big, outputs=[output, sidecar]).start()
t0 = time.time()
while r.poll() == runner.Runner.RUNNING and r.fraction < 0.05 and time.time() - t0 < 120:
    time.sleep(0.1)
check(r.poll() == runner.Runner.RUNNING, "still rendering before the cancel (%.2f)" % r.fraction)
check(r.cancel() == runner.Runner.CANCELLED, "cancelled")
check(not os.path.exists(output) and not os.path.exists(sidecar), "the cancelled run left no output")
print("after the cancel (Wine's SIGTERM: no clean-up by the .exe): %s" % sorted(os.listdir(folder)))

print("wine_runner.py: %d failure(s)" % len(failures))
sys.exit(1 if failures else 0)

"""Presets round-trip through Blender's preset menu; failures (missing executable, the executable
exiting 2, a malformed preset) report an error and leave the world unchanged; the non-blocking
runner's progress parsing and cancel, driven directly as the modal timer would."""

import json
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402

h.install_and_enable()
from firmament_sky import maps, operators, runner, sky_presets  # noqa: E402

scene = bpy.context.scene
p = h.fast_settings(scene)

# --- the menu lists the shipped presets (by their names) -----------------------------------------
names = sorted(sky_presets.display_name(os.path.join(operators.SHIPPED_PRESETS, f))
               for f in os.listdir(operators.SHIPPED_PRESETS))
for want in ("Clear noon", "Golden hour", "Blue hour", "Hazy desert", "Humid coast", "Polar winter", "Smoggy city"):
    h.check(want in names, "shipped preset '%s'" % want)

# --- round trip: load, change, save as a user preset, reset, load it back -------------------------
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("humid-coast"))
h.check(bpy.types.FIRMAMENT_MT_presets.bl_label == "Humid coast", "menu shows the loaded preset's name")
p.turbidity = 2.25
p.hour, p.minute = 7, 45
p.ozone_mode, p.ozone_du = "MANUAL", 333.0
saved = {k: getattr(p, k) for k in ("sun_source", "year", "month", "day", "hour", "minute", "second", "utc_offset",
                                     "latitude", "longitude", "biome", "aerosol_amount", "turbidity", "use_humidity",
                                     "humidity", "ozone_mode", "ozone_du", "albedo", "altitude")}
bpy.ops.firmament_sky.add_preset(name="My Coast Morning")
user_dir = os.path.join(bpy.utils.user_resource("SCRIPTS"), "presets", "firmament_sky")
user_file = os.path.join(user_dir, "My_Coast_Morning.json")
h.check(os.path.isfile(user_file), "user preset written as JSON: %s" % user_file)
written = json.load(open(user_file))
h.check(written["name"] == "My Coast Morning", "the preset keeps the name typed: %r" % written["name"])
h.check(written["latitude"] == 1.2903 and written["longitude"] == 103.852, "latitude and longitude as shown: %r, %r"
        % (written["latitude"], written["longitude"]))
h.check(all(len(repr(v).lstrip("-").replace(".", "")) <= 7 for v in written.values() if isinstance(v, float)),
        "no float noise in the preset's numbers: %s" % {k: v for k, v in written.items() if isinstance(v, float)})
h.check(any(os.path.samefile(user_dir, d) for d in bpy.utils.preset_paths("firmament_sky")),
        "user preset folder is one of Blender's preset paths (the menu lists it)")
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("polar-winter"))
h.check(p.biome == "polar-arctic" and abs(p.albedo - 0.8) < 1e-6, "another preset loaded in between")
bpy.ops.firmament_sky.load_preset(filepath=user_file)
for k, v in saved.items():
    got = getattr(p, k)
    h.check(got == v if not isinstance(v, float) else abs(got - v) < 1e-5, "round trip %s: %r == %r" % (k, got, v))
# the executable accepts the add-on's preset file (one schema)
import subprocess  # noqa: E402
out = tempfile.mkdtemp()
rc = subprocess.run([h.EXE, "render", "--preset", user_file, "--width", "16", "--quality", "preview",
                     "--progress", "none", "-o", os.path.join(out, "s.exr")], capture_output=True, text=True)
h.check(rc.returncode == 0, "firmament render --preset accepts the saved file (%s)" % rc.stderr.strip())
if rc.returncode == 0:
    side = json.load(open(os.path.join(out, "s.json")))
    h.check(abs(side["parameters"]["turbidity"] - 2.25) < 1e-9 and side["parameters"]["ozone_column_du"] == 333,
            "the executable applies the saved values")
# removing the active user preset
bpy.ops.firmament_sky.add_preset(remove_active=True)
h.check(not os.path.exists(user_file), "user preset removed")

# --- the thesis figures (scenes/thesis/) load as presets: their sky, not their view ---------------
thesis = os.path.join(h.ROOT, "scenes", "thesis")
for f in sorted(f for f in os.listdir(thesis) if f.endswith(".json")):
    job = json.load(open(os.path.join(thesis, f)))
    bpy.ops.firmament_sky.load_preset(filepath=os.path.join(thesis, f))
    h.check(p.biome == job["biome"] and p.sun_source == "ANGLES" and abs(p.sun_elevation - job["sun_elevation"]) < 1e-6
            and abs(p.turbidity - job.get("turbidity", p.turbidity)) < 1e-6,
            "thesis job %s loads its sky" % f)

# --- a world to protect ---------------------------------------------------------------------------
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("clear-noon"))
h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "a first sky")


def snapshot():
    nodes = scene.world.node_tree.nodes
    lamp = h.sun_lamps()[0]
    return (scene.world.name, sorted(n.name for n in nodes), [i.name for i in h.world_images()],
            [i.filepath for i in h.world_images()], tuple(lamp.rotation_euler), lamp.data.energy,
            scene.view_settings.exposure, len(bpy.data.images), len(bpy.data.objects))


before = snapshot()


def expect_failure(what, needle):
    try:
        res = bpy.ops.firmament_sky.generate()
        h.check(False, "%s: generate should fail, returned %s" % (what, res))
    except RuntimeError as e:  # an operator's ERROR report raises when called from Python
        h.check(needle in str(e), "%s: error report names the problem: %s" % (what, str(e).strip()))
    h.check(snapshot() == before, "%s: world, images and lamp unchanged" % what)


# missing executable
prefs = bpy.context.preferences.addons["firmament_sky"].preferences
prefs.executable = os.path.join(out, "no-such-firmament")
expect_failure("missing executable", "not found")
prefs.executable = h.EXE
# the real executable exiting 2: its presets folder (FIRMAMENT_PRESETS) has the biomes but no colour config
empty = tempfile.mkdtemp()
os.symlink(os.path.join(h.ROOT, "presets", "biomes"), os.path.join(empty, "biomes"))
os.environ["FIRMAMENT_PRESETS"] = empty
expect_failure("executable exits 2", "(exit 2): firmament: cannot use the OpenColorIO config")
# a biome the executable's table does not list is refused before anything runs
empty = tempfile.mkdtemp()
os.mkdir(os.path.join(empty, "biomes"))
os.symlink(os.path.join(h.ROOT, "presets", "ocio"), os.path.join(empty, "ocio"))
os.environ["FIRMAMENT_PRESETS"] = empty
expect_failure("biome the executable lacks", "biome: unknown 'remote-continental'")
del os.environ["FIRMAMENT_PRESETS"]
h.check(len(os.listdir(maps.cache_dir())) == 1, "the failed run left no folder in the cache")
# values validated before anything runs
p.month, p.day = 2, 30
expect_failure("impossible date", "not a real date")
p.month, p.day = 6, 21
# malformed presets: one message naming the file and the place, settings and world unchanged
settings_before = dict(p.items())
for text, needle in (('{"name": "x", "turbidity": 1,}', ":1:"), ('{"turbidity": 1}', "missing 'name'"),
                     ('{"name": "x", "albedo": 2}', "$.albedo"), ('{"name": "x", "biome": 3}', "$.biome"),
                     ('{"name": "x", "colour": "red"}', "$.colour")):
    bad = os.path.join(out, "bad.json")
    open(bad, "w").write(text)
    try:
        bpy.ops.firmament_sky.load_preset(filepath=bad)
        h.check(False, "malformed preset %s accepted" % text)
    except RuntimeError as e:
        h.check(needle in str(e) and "bad.json" in str(e), "malformed preset: %s" % str(e).strip())
    h.check(dict(p.items()) == settings_before and snapshot() == before, "malformed preset changed nothing")

# --- the sun given by angles with the ozone from the climatology: its column depends on the whole
# place, so the command passes the longitude as well as the latitude, and the executable takes them
from firmament_sky import command, options, properties  # noqa: E402
angles = properties.defaults()
angles.update(sun_source="ANGLES", ozone_mode="AUTO", latitude=-33.9, longitude=151.2, resolution=16, quality="preview")
folder = tempfile.mkdtemp()
args = command.build_arguments(h.EXE, options.load(h.EXE), angles, os.path.join(folder, "a.exr"), os.path.join(folder, "a.json"))
given = dict(zip(args, args[1:]))
h.check(given.get("--longitude") == "151.2" and given.get("--latitude") == "-33.9",
        "angles + climatology ozone: the place passed: %s" % args)
done = subprocess.run(args, capture_output=True, text=True)
side = json.load(open(os.path.join(folder, "a.json"))) if done.returncode == 0 else {}
h.check(side.get("parameters", {}).get("longitude_deg") == 151.2,
        "angles + climatology ozone renders at that longitude: %s %s" % (done.stderr, side.get("parameters")))

# --- the sun given by angles with a given ozone column: the date still sets the Earth-Sun distance,
# as it does for a clock time on that date
angles.update(ozone_mode="MANUAL", ozone_du=300.0, year=2024, month=1, day=3)
args = command.build_arguments(h.EXE, options.load(h.EXE), angles, os.path.join(folder, "m.exr"), os.path.join(folder, "m.json"))
done = subprocess.run(args, capture_output=True, text=True)
side = json.load(open(os.path.join(folder, "m.json"))) if done.returncode == 0 else {}
params = side.get("parameters", {})
h.check(params.get("earth_sun_distance_from") == "date" and abs(params.get("earth_sun_distance_au", 0) - 0.9833) < 2e-4,
        "angles + given ozone: the date's Earth-Sun distance: %s %s" % (done.stderr, params))

# --- the non-blocking runner, polled as the modal timer does, then cancelled ----------------------
for line, want in (('{"event": "progress", "fraction": 0.42, "stage": "multiple scattering"}', (0.42, "multiple scattering")),
                   ('{"event": "progress", "fraction": 1.7, "stage": "x"}', (1.0, "x")),
                   ('{"event": "progress", "fraction": "half"}', None), ("not json", None), ("[1, 2]", None),
                   ('{"event": "done", "seconds": 3.1}', "done")):
    got = runner.parse_progress_line(line)
    if want is None:
        h.check(got is None, "progress line ignored: %s" % line)
    elif want == "done":
        h.check(got and got["event"] == "done" and got["seconds"] == 3.1, "done event parsed")
    else:
        h.check(got and (got["fraction"], got["stage"]) == want, "progress parsed: %s" % line)
folder = tempfile.mkdtemp()
exr, side = os.path.join(folder, "big.exr"), os.path.join(folder, "big.json")
r = runner.Runner([h.EXE, "render", "--width", "2048", "--quality", "final", "--threads", "1", "--progress", "json",
                   "-o", exr, "--sidecar", side], outputs=[exr, side]).start()
seen, t0 = [], time.time()
while time.time() - t0 < 60 and r.poll() == runner.Runner.RUNNING:
    if r.fraction > 0.0:
        seen.append(r.fraction)
    if len(seen) >= 3 and r.fraction > 0.1:
        break
    time.sleep(0.1)
h.check(len(seen) >= 3 and seen == sorted(seen) and r.stage not in ("", "starting"),
        "progress read while running: %d values up to %.3f, stage '%s'" % (len(seen), max(seen or [0]), r.stage))
h.check(r.poll() == runner.Runner.RUNNING, "still running before cancel")
state = r.cancel()
h.check(state == runner.Runner.CANCELLED and r.returncode in (143, -15), "cancelled: exit %s" % r.returncode)
h.check(os.listdir(folder) == [], "cancel left no file: %s" % os.listdir(folder))
# a failing child in the runner: its stderr is the message
r = runner.Runner([h.EXE, "render", "--turbidity", "-1"]).start()
h.check(r.wait() == runner.Runner.FAILED and r.returncode == 2 and "--turbidity" in r.error_text(),
        "exit 2 with its stderr line: %s" % r.error_text())
try:
    runner.Runner("firmament render --width 8")
    h.check(False, "a command string is refused (no shell)")
except TypeError:
    h.check(True, "a command string is refused (no shell)")
h.finish()

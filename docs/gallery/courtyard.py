"""The gallery's Blender image: the demo courtyard (scenes/demo_courtyard.py) at golden hour, lit by
a world the add-on generates with firmament (the shipped preset "Golden hour"), rendered with Cycles
on the CPU.  Run by docs/gallery/render, headless, with an isolated user profile:

  blender -b --factory-startup --python-exit-code 1 -t 1 -P docs/gallery/courtyard.py -- \
      ADDON.zip FIRMAMENT OUT.png INFO.json WIDTH HEIGHT SAMPLES MAP_WIDTH MAP_QUALITY THREADS

INFO.json records what the caption needs: the sun, the exposure, the render settings and times."""

import json
import math
import os
import sys
import time

import addon_utils
import bpy

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scenes"))
import demo_courtyard  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
if len(argv) != 10:
    raise SystemExit("courtyard.py: expected 10 arguments after --, got %d" % len(argv))
ZIP, EXE, OUT_PNG, OUT_INFO = argv[:4]
WIDTH, HEIGHT, SAMPLES, MAP_WIDTH = (int(a) for a in argv[4:8])
QUALITY, THREADS = argv[8], int(argv[9])  # THREADS 0: every core
PRESET = "golden-hour"

# the add-on as a user installs it: the built zip, enabled, pointed at this build's executable
bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
if addon_utils.enable("firmament_sky", default_set=True, handle_error=None) is None:
    raise SystemExit("courtyard.py: the add-on did not enable")
bpy.context.preferences.addons["firmament_sky"].preferences.executable = EXE

scene = bpy.context.scene
demo_courtyard.build(scene)
preset = os.path.join(bpy.utils.user_resource("SCRIPTS"), "addons", "firmament_sky", "presets", "skies",
                      PRESET + ".json")
if bpy.ops.firmament_sky.load_preset(filepath=preset) != {"FINISHED"}:
    raise SystemExit("courtyard.py: cannot load the preset " + preset)
p = scene.firmament_sky
p.resolution = MAP_WIDTH
p.quality = QUALITY
p.threads = THREADS
p.sun_mode = "LAMP"  # the default: map without the disk + a matching Sun lamp
p.apply_exposure = False  # metered below, for the low sun
t0 = time.monotonic()
if bpy.ops.firmament_sky.generate() != {"FINISHED"}:
    raise SystemExit("courtyard.py: Generate Sky failed: " + p.last_message)
sky_seconds = time.monotonic() - t0
sidecar_path = os.path.splitext(bpy.path.abspath(
    next(img for img in bpy.data.images if img.get("firmament_sky")).filepath))[0] + ".json"
with open(sidecar_path) as f:
    sidecar = json.load(f)
# The sidecar's suggested exposure meters a horizontal white card; with the sun 5 degrees up the
# facades facing it get several times that light and would clip.  Meter a white card facing the sun
# instead (direct normal + diffuse horizontal illuminance), by the same rule: EV = log2(683 pi / E).
facing_sun_lux = sidecar["sun"]["direct_normal_illuminance_lux"] + sidecar["sky"]["diffuse_horizontal_illuminance_lux"]
scene.view_settings.exposure = math.log2(683.0 * math.pi / facing_sun_lux)
# the scene's 60 m paving ends where the map's own ground (albedo 0.2) begins: widen it to 30 km so
# that it meets the sky at the horizon (its edge 0.013 degrees below the horizontal: under a pixel)
bpy.data.objects["Ground"].scale = (500.0, 500.0, 1.0)

r = scene.render
r.resolution_x, r.resolution_y, r.resolution_percentage = WIDTH, HEIGHT, 100
if THREADS > 0:
    r.threads_mode, r.threads = "FIXED", THREADS
scene.cycles.device = "CPU"
scene.cycles.samples = SAMPLES
scene.cycles.use_adaptive_sampling = True
scene.cycles.use_denoising = False  # Debian's Blender is built without OpenImageDenoise
scene.cycles.max_bounces = 6
scene.world.cycles.sample_map_resolution = 1024
r.image_settings.file_format = "PNG"
r.image_settings.color_mode = "RGB"
r.image_settings.color_depth = "8"
r.filepath = OUT_PNG
t0 = time.monotonic()
bpy.ops.render.render(write_still=True)
render_seconds = time.monotonic() - t0
if not os.path.isfile(OUT_PNG):
    raise SystemExit("courtyard.py: the render wrote no " + OUT_PNG)

info = {
    "blender": bpy.app.version_string,
    "preset": PRESET,
    "sky": sidecar["parameters"],
    "solar_position": sidecar.get("solar_position", {}),
    "sun_elevation_deg": sidecar["sun"]["elevation_deg"],
    "sun_azimuth_deg": sidecar["sun"]["azimuth_deg"],
    "global_horizontal_illuminance_lux": sidecar["sky"]["global_horizontal_illuminance_lux"],
    "exposure_ev": scene.view_settings.exposure,
    "suggested_exposure_ev": sidecar["sky"]["suggested_exposure_ev"],
    "facing_sun_illuminance_lux": facing_sun_lux,
    "view_transform": scene.view_settings.view_transform,
    "map_width": MAP_WIDTH,
    "map_quality": QUALITY,
    "sun_mode": p.sun_mode,
    "width": WIDTH, "height": HEIGHT,
    "samples": SAMPLES,
    "max_bounces": scene.cycles.max_bounces,
    "sky_seconds": round(sky_seconds, 1),
    "render_seconds": round(render_seconds, 1),
}
with open(OUT_INFO, "w") as f:
    json.dump(info, f, indent=1)
print("courtyard.py: sky %.1f s, render %.1f s, exposure %.2f EV" % (sky_seconds, render_seconds,
                                                                     scene.view_settings.exposure))

"""Clouds in the add-on: the shipped cloud presets load their cloud settings, Generate passes them to
the executable, and the Sun lamp is dimmed exactly as the sidecar says.  High cirrostratus (ice, tau
0.5): the lamp's irradiance over the same sky without the veil is the sidecar's cloud transmittance
(the crystals' extinction does not depend on wavelength, so every channel falls alike); Overcast
(stratus, tau 30): the disk is hidden, the lamp's strength is nothing and it is switched off (the sky
carries the light).  In Live under the deck, a moved sun or a thicker deck keeps the lamp off until
its map comes; with the clouds removed it shines at once.
Maps 32 pixels wide, preview quality."""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402

h.install_and_enable()
scene = bpy.context.scene


def generate():
    res = bpy.ops.firmament_sky.generate()
    h.check(res == {"FINISHED"}, "generate finished (%s)" % scene.firmament_sky.last_message)
    side = h.sidecar_of(h.sky_image())
    lamps = h.sun_lamps()
    h.check(len(lamps) == 1, "one sun lamp")
    lamp = lamps[0]
    return side, [lamp.data.energy * c for c in lamp.data.color], lamp


bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("high-cirrostratus"))
p = h.fast_settings(scene, width=32)
h.check(p.cloud == "cirrostratus" and p.cloud_amount == "TAU" and abs(p.cloud_tau - 0.5) < 1e-6,
        "preset's cloud: %s, %s %.3g" % (p.cloud, p.cloud_amount, p.cloud_tau))
side, veiled, lamp = generate()
h.check(not lamp.hide_render, "cirrostratus: the lamp shines")
a = side["atmosphere"]
h.check(a.get("cloud_1_type") == "cirrostratus" and abs(a["cloud_1_optical_depth_550nm"] - 0.5) < 1e-9,
        "sidecar: the layer (%s, %s)" % (a.get("cloud_1_type"), a.get("cloud_1_optical_depth_550nm")))
rgb = side["sun"]["direct_normal_irradiance_rgb"]
for c in range(3):
    h.close(veiled[c], rgb[c], 1e-4 * rgb[c], "lamp strength x colour [%d] = sidecar irradiance" % c)
t = side["sun"]["cloud_direct_transmittance_550nm"]
h.check(0.3 < t < 0.7, "cirrostratus transmittance %.4f" % t)

p.cloud = "none"  # the same sky without the veil
side_clear, clear, _ = generate()
h.check("cloud_layers" not in side_clear["atmosphere"], "no clouds in the clear sidecar")
for c in range(3):
    h.close(veiled[c] / clear[c], t, 1e-3 * t, "lamp dimmed by the sidecar's cloud transmittance [%d]" % c)

bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("overcast"))
p = h.fast_settings(scene, width=32)
h.check(p.cloud == "stratus" and p.cloud_amount == "DEFAULT", "overcast: stratus at its own optical depth")
side, hidden, lamp = generate()
h.check(side["sun"]["cloud_direct_transmittance_550nm"] < 1e-12, "overcast: the disk is hidden (T = %.3g)"
        % side["sun"]["cloud_direct_transmittance_550nm"])
h.check(max(hidden) < 1e-9 * max(clear), "overcast: the lamp's strength is nothing (%.3g)" % max(hidden))
h.check(lamp.hide_render and lamp.hide_viewport, "overcast: the lamp is off")
h.check(side["sky"]["diffuse_horizontal_illuminance_lux"] > 0.0, "overcast: the sky carries the light")

# Live under the deck: each change turns the lamp at once and keeps the deck's verdict (the lamp's
# last sidecar) until its map comes, unless the settings have no cloud.  (A cloudy live atmosphere
# takes minutes to build: only the lamp before any map is checked, and Live is turned off.)
live = h.submodule("live")
p.live = True
h.check(lamp.hide_render and lamp.hide_viewport, "Live on under the deck: the lamp stays off")
pid = live._state["server"].pid
for what, key, value in (("the sun moved", "sun_elevation", 50.0), ("the deck thickened", "cloud_tau", 40.0)):
    if key == "sun_elevation":
        p.sun_source = "ANGLES"
    else:
        p.cloud_amount = "TAU"
    setattr(p, key, value)
    live.watch()  # the event loop's next pass (headless: called here)
    h.check(lamp.hide_render and lamp.hide_viewport, "Live, %s: the lamp stays off until the map" % what)
p.cloud = "none"
live.watch()
h.check(not lamp.hide_render and not lamp.hide_viewport, "Live, the clouds removed: the lamp on at once")
h.check(abs(lamp.rotation_euler.to_matrix().col[2].z - math.sin(math.radians(50.0))) < 1e-6,
        "Live: the lamp toward the 50 degree sun")
p.live = False
h.check(live._state["server"] is None and not os.path.exists("/proc/%d" % pid), "Live off: the server is gone")
h.finish()

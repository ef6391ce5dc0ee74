"""EEVEE: a generated sky (lamp mode) renders in EEVEE (BLENDER_EEVEE in 3.4 and 5.0,
BLENDER_EEVEE_NEXT in 4.2-4.5): the lamp is present with the sidecar's angular diameter, EEVEE
extracts no second sun from the map, and the frame is not black: a white card lit by sun and sky
(its luminance within 25% of the sidecar's global illuminance / (683 pi): EEVEE's world lighting
is approximate), sunlit ground brighter than shade."""

import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402

h.install_and_enable()
world = h.submodule("world")
scene = bpy.context.scene
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("clear-noon"))
h.fast_settings(scene, width=64)
h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate")
side = h.sidecar_of(h.sky_image())
cam = h.card_scene(scene)
engine = world.eevee_engine()
h.check(engine == ("BLENDER_EEVEE_NEXT" if (4, 2, 0) <= bpy.app.version < (5, 0, 0) else "BLENDER_EEVEE"),
        "EEVEE's engine id in Blender %s: %s" % (bpy.app.version_string, engine))
h.render_settings(scene, res=(32, 32), engine=engine)
if hasattr(scene.eevee, "taa_render_samples"):
    scene.eevee.taa_render_samples = 4
lamps = h.sun_lamps()
h.check(len(lamps) == 1 and not lamps[0].hide_render, "the sun lamp renders")
h.close(math.degrees(lamps[0].data.angle), side["sun"]["angular_diameter_deg"], 1e-4, "lamp angle (soft shadows)")
if hasattr(scene.world, "sun_threshold"):
    h.check(scene.world.sun_threshold == 0.0, "EEVEE extracts no sun from the map (threshold 0)")
t0 = time.time()
pix, w, hgt = h.render_linear(scene, os.path.join(h.OUT, "eevee.exr"))
print("EEVEE frame %dx%d in %.1f s" % (w, hgt, time.time() - t0))
cls = h.classify(scene, cam, w, hgt)
lit, shade, card = (h.mean_luminance(pix, cls[k]) for k in ("lit", "shade", "card"))
h.check(min(len(cls[k]) for k in ("lit", "shade", "card")) >= 4, "pixels: %s" % {k: len(v) for k, v in cls.items()})
h.check(lit > 1.5 * shade > 0.0, "not black, sunlit ground brighter than shade: %.4g vs %.4g" % (lit, shade))
expected = side["sky"]["global_horizontal_illuminance_lux"] / 683.0 / math.pi
h.close(card / expected, 1.0, 0.25, "white card / (E_global / 683 pi) (%.4g vs %.4g)" % (card, expected))
h.finish()

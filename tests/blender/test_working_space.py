"""Blender 5.0's working colour spaces: the same sky generated in a file working in Linear Rec.709,
Linear Rec.2020 and ACEScg lights a white card to the same luminance (CIE Y, from each space's own
RGB -> XYZ row) within 1%: the map is converted by Blender from its Linear Rec.709 tag, the lamp's
colour by the add-on."""

import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402

if not hasattr(bpy.data, "colorspace"):
    print("SKIP: Blender %s has no working colour space setting (5.0+)" % bpy.app.version_string)
    sys.exit(77)
h.install_and_enable()
scene = bpy.context.scene
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("golden-hour"))  # a coloured sun and sky
h.fast_settings(scene)
cam = h.card_scene(scene)
card = {}
for ws in ("Linear Rec.709", "Linear Rec.2020", "ACEScg"):
    bpy.ops.wm.set_working_color_space(working_space=ws)
    h.check(bpy.data.colorspace.working_space == ws, "working space %s" % ws)
    h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate in %s" % ws)
    h.render_settings(scene)
    pix, w, hgt = h.render_linear(scene, os.path.join(h.OUT, "card_%s.exr" % ws.replace(" ", "_")))
    cls = h.classify(scene, cam, w, hgt)
    card[ws] = h.mean_luminance(pix, cls["card"])
    print("card luminance in %s: %.5g" % (ws, card[ws]))
ref = card["Linear Rec.709"]
for ws in ("Linear Rec.2020", "ACEScg"):
    h.close(card[ws] / ref, 1.0, 0.01, "white card luminance in %s / in Linear Rec.709" % ws)
h.finish()

"""In every Blender version: install the built zip through that Blender's own install path, enable it
with no preference set, Generate a shipped preset through the bundled executable, and check the
world's node tree, the image's colour space, the lamp against the sidecar, the sun counted once, and a
small Cycles render: sunlit ground brighter than shade, a white card's luminance = the sidecar's
global horizontal illuminance / (683 pi) within 5%."""

import math
import os
import stat
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402
from mathutils import Color, Vector  # noqa: E402

h.install_and_enable()
prefs_mod = h.submodule("preferences")
bundled = os.path.join(h.addon_dir(), "bin", "firmament")
exe, where = prefs_mod.find_executable(h.preferences().executable)
h.check(exe == bundled and where.startswith("bundled"), "the bundled executable is used: %s (%s)" % (exe, where))
h.check(os.stat(bundled).st_mode & stat.S_IXUSR, "the bundled executable is executable")

scene = bpy.context.scene
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("clear-noon"))
p = h.fast_settings(scene)
h.check(p.sun_mode == "LAMP", "default sun mode: the lamp")
res = bpy.ops.firmament_sky.generate()
h.check(res == {"FINISHED"}, "generate: %s" % res)

# the world: Texture Coordinate (Generated) -> Mapping -> Environment Texture -> Background -> Output
sky = h.sky_image()
side = h.sidecar_of(sky)
nodes = scene.world.node_tree.nodes
out = [n for n in nodes if n.type == "OUTPUT_WORLD" and n.is_active_output][0]
bg = out.inputs["Surface"].links[0].from_node
h.check(bg.type == "BACKGROUND" and abs(bg.inputs["Strength"].default_value - 1.0) < 1e-9, "background, strength 1")
env = h.env_of(bg)
h.check(env.type == "TEX_ENVIRONMENT" and env.image == sky, "environment texture holds the map")
disk = nodes.get("Firmament Sun Disk")
h.check(disk is not None and bg.inputs["Color"].links[0].from_node == disk, "the camera-only sun disk feeds the background")
mapping = env.inputs["Vector"].links[0].from_node
h.check(mapping.type == "MAPPING" and mapping.vector_type == "POINT", "mapping node (point)")
tc = mapping.inputs["Vector"].links[0]
h.check(tc.from_node.type == "TEX_COORD" and tc.from_socket.name == "Generated", "generated coordinates")
h.check(sky.is_float and tuple(sky.size) == (128, 64), "float map 128 x 64: %s" % (tuple(sky.size),))
h.check(sky.colorspace_settings.name in ("Linear Rec.709", "Linear") and side["image"]["colorspace"] == "Linear Rec.709",
        "image tagged %s, the sidecar's %s" % (sky.colorspace_settings.name, side["image"]["colorspace"]))

# the lamp against the sidecar: direction 0.1 deg, strength x colour (back in Rec.709) 1e-3
lamps = h.sun_lamps()
h.check(len(lamps) == 1, "one sun lamp (%d)" % len(lamps))
lamp = lamps[0]
got = lamp.matrix_world.to_3x3() @ Vector((0, 0, 1))
ang = math.degrees(got.angle(Vector(side["sun"]["direction"])))
h.check(ang < 0.1, "lamp direction within 0.1 deg of the sidecar's (%.5f deg)" % ang)
rgb = Color([lamp.data.energy * c for c in lamp.data.color]).from_scene_linear_to_rec709_linear()
want = side["sun"]["direct_normal_irradiance_rgb"]
for c in range(3):
    h.close(rgb[c] / want[c], 1.0, 1e-3, "lamp strength x colour [%d] / sidecar irradiance" % c)
h.close(math.degrees(lamp.data.angle), side["sun"]["angular_diameter_deg"], 1e-4, "lamp angle = sun's diameter")
# the sun counted once: the lighting map holds no disk (no pixel carries a sizeable part of its energy)
h.check(not side["image"]["contains_sun_disk"], "the sidecar says the map has no disk")
px = h.image_pixels(sky)
w, hgt = sky.size
best = max(px[4 * (y * w + x) + 1] * (2 * math.pi / w) * (math.pi / hgt) * math.cos((y + 0.5) / hgt * math.pi - math.pi / 2)
           for y in range(hgt) for x in range(w))
h.check(best < 0.02 * want[1], "no map pixel holds the disk's energy (%.3g vs DNI %.3g)" % (best, want[1]))
if hasattr(scene.world, "sun_threshold"):
    h.check(scene.world.sun_threshold > 1e3 or getattr(scene.world, "use_sun_shadow", True) is False or
            scene.world.sun_threshold == 0.0, "EEVEE extracts no second sun from the map (threshold %g)"
            % scene.world.sun_threshold)

# undo: Generate is one step; undo brings back the previous world, lamp and exposure with their map
# (still on disk), redo the new one
def state():
    img = h.sky_image()
    lamp = h.sun_lamps()[0]
    return (img.filepath, tuple(round(a, 6) for a in lamp.rotation_euler), round(lamp.data.energy, 4),
            round(bpy.context.scene.view_settings.exposure, 4))  # undo replaces the scene's Python object


first = state()
bpy.ops.ed.undo_push(message="before")  # background mode starts with undo off: this turns it on
p.hour, p.apply_exposure = 17, True
# undo=True: pushes the operator's undo step as a click in the UI does (scripts default to no push)
h.check(bpy.ops.firmament_sky.generate("EXEC_DEFAULT", True) == {"FINISHED"}, "generate again (17:00, exposure set)")
second = state()
h.check(second != first, "the second sky differs")
bpy.ops.ed.undo()
h.check(state() == first, "undo restores the previous sky, lamp and exposure: %s" % (state(),))
h.check(os.path.isfile(bpy.path.abspath(h.sky_image().filepath)), "undo: its map is on disk")
bpy.ops.ed.redo()
h.check(state() == second, "redo brings back the generated sky")
h.check(os.path.isfile(bpy.path.abspath(h.sky_image().filepath)), "redo: its map is on disk")
bpy.ops.ed.undo()  # the render below checks the first sky against its sidecar
scene = bpy.context.scene
side = h.sidecar_of(h.sky_image())

# a small Cycles render
cam = h.card_scene(scene)
h.render_settings(scene)
pix, rw, rh = h.render_linear(scene, os.path.join(h.OUT, "card.exr"))
cls = h.classify(scene, cam, rw, rh)
h.check(all(len(cls[k]) >= 12 for k in ("card", "lit", "shade")), "pixels: %s" % {k: len(v) for k, v in cls.items()})
lit, shade, card = (h.mean_luminance(pix, cls[k]) for k in ("lit", "shade", "card"))
h.check(lit > 2.0 * shade, "sunlit ground brighter than shade: %.4g vs %.4g" % (lit, shade))
expected = side["sky"]["global_horizontal_illuminance_lux"] / 683.0 / math.pi
h.close(card / expected, 1.0, 0.05, "white card luminance / (E_global / 683 pi) (%.4g vs %.4g)" % (card, expected))
h.finish()

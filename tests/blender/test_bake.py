"""Bake a day: 6 maps (07:00 to 17:00 every 2 hours); the world plays them as an image sequence and
the lamp is keyframed from each frame's sidecar (direction 0.1 deg, strength 1e-3); the saved .blend
rendered as an animation in a new process (3.4: `blender -b file.blend -a`) shows each frame's own
sky (the map's nadir seen past the ground) and light (a white card = that frame's global horizontal
illuminance / (683 pi), within 5%).  Then through sunset into the night (the lamp hidden below the
horizon), and the scene's frame range mapped to clock times (frames 11-13 from 08:00 to 15:01: each
frame's map at its linearly mapped time, to the second, rendered as an animation)."""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402
from mathutils import Color, Vector  # noqa: E402


def check_animation(sides, prefix):
    """The rendered frames (PREFIX####.exr, from the scene's first frame) against their maps: a white
    card at its sidecar's global illuminance, the world below at its own map's nadir.  Returns the
    cards' luminances."""
    cards = []
    folder = os.path.dirname(bpy.path.abspath(h.sky_image().filepath))
    for i, side in enumerate(sides):
        f = scene.frame_start + i
        scene.frame_set(f)
        pix, w, hgt = h.load_linear(os.path.join(h.OUT, "%s%04d.exr" % (prefix, f)))
        cls = h.classify(scene, cam, w, hgt)
        card = h.mean_luminance(pix, cls["card"])
        expected = side["sky"]["global_horizontal_illuminance_lux"] / 683.0 / math.pi
        h.close(card / expected, 1.0, 0.05, "frame %d: white card / its sidecar's E_global / (683 pi) (%.3g vs %.3g)"
                % (f, card, expected))
        # the world straight down, past the ground, is the frame's own map at the nadir: u = 0.5 (between
        # columns w/2 - 1 and w/2), v = 0, where Blender's linear lookup wraps and mixes the bottom and
        # top rows half and half
        mp, mw, mh = h.load_linear(os.path.join(folder, "sky_%04d.exr" % i))
        at = [4 * (row * mw + col) for row in (0, mh - 1) for col in (mw // 2 - 1, mw // 2)]
        own = sum(h.luminance(mp[k:k + 3]) for k in at) / 4
        seen = h.mean_luminance(pix, cls["sky"])
        h.close(seen / own, 1.0, 1e-3, "frame %d: the world below shows its own map's nadir (%.4g vs %.4g, %d px)"
                % (f, seen, own, len(cls["sky"])))
        cards.append(card)
    return cards


def render_saved(name, sides):
    """Saves the file as OUT/NAME/NAME.blend, renders its animation in a new process (OUT/NAME_####.exr)
    and checks the frames (check_animation)."""
    scene.render.filepath = os.path.join(h.OUT, name + "_")
    blend = os.path.join(h.OUT, name, name + ".blend")
    os.makedirs(os.path.dirname(blend))
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    h.render_in_new_process(blend)
    return check_animation(sides, name + "_")


h.install_and_enable()
scene = bpy.context.scene
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("clear-noon"))
p = h.fast_settings(scene, width=32)
p.bake_start, p.bake_end, p.bake_step_min = 7.0, 17.0, 120
cam = h.card_scene(scene, ground_half=4.5, ortho_scale=12.0)
scene.frame_start = 1
h.check(bpy.ops.firmament_sky.bake_day() == {"FINISHED"}, "bake a day")
h.check((scene.frame_start, scene.frame_end) == (1, 6), "frame range 1-6: %d-%d" % (scene.frame_start, scene.frame_end))
env = scene.world.node_tree.nodes["Firmament Sky"]
sky = h.sky_image()
h.check(env.image == sky and sky.source == "SEQUENCE", "the environment texture plays an image sequence")
lamp = h.sun_lamps()[0]
sides = []
for f in range(1, 7):
    scene.frame_set(f)
    # frame f is the series' map f - 1 (the render below checks that it shows it)
    path = os.path.join(os.path.dirname(bpy.path.abspath(sky.filepath)), "sky_%04d.exr" % (f - 1))
    side = h.sidecar_of(type("Image", (), {"filepath": path})())
    sides.append(side)
    got = lamp.matrix_world.to_3x3() @ Vector((0, 0, 1))
    ang = math.degrees(got.angle(Vector(side["sun"]["direction"])))
    h.check(ang < 0.1, "frame %d: lamp direction within 0.1 deg of its sidecar (%.4f deg)" % (f, ang))
    rgb = Color([lamp.data.energy * c for c in lamp.data.color]).from_scene_linear_to_rec709_linear()
    want = side["sun"]["direct_normal_irradiance_rgb"]
    h.check(all(abs(rgb[c] / want[c] - 1) < 1e-3 for c in range(3)), "frame %d: lamp strength x colour = sidecar's" % f)
h.check(len({round(s["sun"]["elevation_deg"], 3) for s in sides}) == 6, "six different suns")

# render the animation from the saved file in a new process
h.render_settings(scene, res=(32, 32), samples=8)
r = scene.render
r.image_settings.file_format = "OPEN_EXR"
r.image_settings.color_depth = "32"
cards = render_saved("day", sides)
h.check(cards[0] < 0.5 * cards[2], "frame 1 (07:00) darker than frame 3 (11:00): %.3g vs %.3g" % (cards[0], cards[2]))

# through sunset into the night (sunset 21:17 in Munich that day; -18 deg near 23:50): the lamp is
# hidden on the frames whose sun is below the horizon, the exposure keyframed only where it meters
p = scene.firmament_sky
p.resolution, p.bake_start, p.bake_end, p.bake_step_min, p.apply_exposure = 16, 20.0, 23.98, 60, True
h.check(bpy.ops.firmament_sky.bake_day() == {"FINISHED"}, "bake 20:00 to 23:59 (sunset and night)")
h.check(scene.frame_end - scene.frame_start + 1 == 4, "four frames: %d-%d" % (scene.frame_start, scene.frame_end))
lamp = h.sun_lamps()[0]
folder = os.path.dirname(bpy.path.abspath(h.sky_image().filepath))
for f in range(scene.frame_start, scene.frame_end + 1):
    scene.frame_set(f)
    el = h.sidecar_of(type("Image", (), {"filepath": os.path.join(folder, "sky_%04d.exr" % (f - 1))})())["sun"]["elevation_deg"]
    h.check(lamp.hide_render == (el < -0.27), "frame %d (sun %.1f deg): lamp %s" % (f, el, "hidden" if lamp.hide_render else "shown"))

# the scene's frame range mapped to clock times: frames 11-13 from 08:00 to 15:01, linearly (a step
# of 210.5 min: 08:00:00, 11:30:30, 15:01:00); the frame range stays, the animation renders each
# frame with its own sky and light
p.bake_timing, p.resolution, p.apply_exposure = "FRAME_RANGE", 32, False
p.bake_start, p.bake_end = 8.0, 15.0 + 1.0 / 60.0
scene.frame_start, scene.frame_end = 11, 13
h.check(bpy.ops.firmament_sky.bake_day() == {"FINISHED"}, "bake frames 11-13 from 08:00 to 15:01")
h.check((scene.frame_start, scene.frame_end) == (11, 13), "frame range kept: %d-%d" % (scene.frame_start, scene.frame_end))
folder = os.path.dirname(bpy.path.abspath(h.sky_image().filepath))
sides = [h.sidecar_of(type("Image", (), {"filepath": os.path.join(folder, "sky_%04d.exr" % i)})()) for i in range(3)]
h.check(not os.path.exists(os.path.join(folder, "sky_0003.exr")), "three maps, one per frame")
lamp = h.sun_lamps()[0]
for i, side in enumerate(sides):
    f = 11 + i
    want = 8 * 3600 + round(i * (7 * 3600 + 60) / 2)  # frame f at 08:00 + (f - 11) / (13 - 11) x 7 h 01 min
    hh, mm, ss = (int(v) for v in side["parameters"]["time"].split(":"))
    h.check(hh * 3600 + mm * 60 + ss == want, "frame %d at %s (expected %02d:%02d:%02d)"
            % (f, side["parameters"]["time"], want // 3600, want // 60 % 60, want % 60))
    scene.frame_set(f)
    ang = math.degrees((lamp.matrix_world.to_3x3() @ Vector((0, 0, 1))).angle(Vector(side["sun"]["direction"])))
    h.check(ang < 0.1, "frame %d: lamp direction within 0.1 deg of its sidecar (%.4f deg)" % (f, ang))
cards = render_saved("range", sides)
h.check(cards[0] < 0.8 * cards[1], "frame 11 (08:00) darker than frame 12 (11:30): %.3g vs %.3g" % (cards[0], cards[1]))
h.finish()

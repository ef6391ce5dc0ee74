"""Art direction: Sky Strength x and Sun Strength x scale the map and the lamp (a white card then
shows 0.5 x the direct + 2 x the diffuse illuminance / (683 pi), within 5%); the ground below the
horizon replaced by a colour lit by this sky (the world straight down shows reflectance x global
illuminance / (683 pi) x sky strength) or hidden (black)."""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402

h.install_and_enable()
scene = bpy.context.scene
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("clear-noon"))
p = h.fast_settings(scene, width=64)
p.sky_strength, p.sun_strength = 2.0, 0.5
p.ground, p.ground_colour = "COLOUR", (0.5, 0.4, 0.3)
h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate with strengths 2 (sky), 0.5 (sun), a ground colour")
side = h.sidecar_of(h.sky_image())
lamp = h.sun_lamps()[0]
h.close(lamp.data.energy / max(side["sun"]["direct_normal_irradiance_rgb"]), 0.5, 2e-3, "lamp strength x 0.5")
cam = h.card_scene(scene, ground_half=4.5, ortho_scale=12.0)
h.render_settings(scene, res=(32, 32), samples=16)
pix, w, hgt = h.render_linear(scene, os.path.join(h.OUT, "art.exr"))
cls = h.classify(scene, cam, w, hgt)
e_dir, e_dif = side["sun"]["direct_horizontal_illuminance_lux"], side["sky"]["diffuse_horizontal_illuminance_lux"]
want = (0.5 * e_dir + 2.0 * e_dif) / (683.0 * math.pi)
h.close(h.mean_luminance(pix, cls["card"]) / want, 1.0, 0.05, "white card under 0.5 x sun + 2 x sky")
ground = h.luminance((0.5, 0.4, 0.3)) * side["sky"]["global_horizontal_illuminance_lux"] / (683.0 * math.pi) * 2.0
h.close(h.mean_luminance(pix, cls["sky"]) / ground, 1.0, 1e-3, "below the horizon: the ground colour lit by this sky")

p.ground = "BLACK"
h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate with the ground hidden")
pix, w, hgt = h.render_linear(scene, os.path.join(h.OUT, "art_black.exr"))
h.check(h.mean_luminance(pix, cls["sky"]) < 1e-6, "below the horizon: black (%.3g)" % h.mean_luminance(pix, cls["sky"]))
h.finish()

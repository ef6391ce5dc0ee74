"""The camera-only sun disk of the default Sun Lamp mode stands out of its aureole at the suggested
exposure, through this Blender's default view transform (Filmic in 3.x, AgX from 4.0), under a clear
and a hazy sky: a camera aimed at the sun (0.31 deg a pixel, the disk 0.53 deg across, centred on
the middle pixel) shows the disk's pixel at least MARGIN brighter than every aureole pixel 2 pixels
(0.63-0.89 deg, 1.2-1.7 disk diameters) from it.  The highlight roll-off that makes this possible
acts on camera rays only: a white card under the hazy sky is lit the same (within 1%) with the
feature and without it."""

import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

# Display-linear (the 16-bit PNG read back) difference between the disk and the aureole beside it:
# 5% of white is 2-5 times the eye's contrast threshold near white (Weber fraction 1-2%) and about
# 6 code values in an 8-bit sRGB file, so the disk is seen as a disk, not a white blot.
MARGIN = 0.05

h.install_and_enable()
scene = bpy.context.scene
vt = scene.view_settings
default_vt = vt.view_transform
h.check(default_vt == ("Filmic" if bpy.app.version < (4, 0, 0) else "AgX"),
        "this Blender's default view transform: %s" % default_vt)
cam = h.card_scene(scene, ground_half=4.5, ortho_scale=12.0)
sun_cam = bpy.data.objects.new("Sun camera", bpy.data.cameras.new("Sun camera"))
sun_cam.data.lens, sun_cam.data.sensor_width, sun_cam.data.sensor_fit = 200.0, 36.0, "HORIZONTAL"
sun_cam.location = (0.0, 0.0, 10.0)  # above the scene: nothing between it and the sun
scene.collection.objects.link(sun_cam)
N = 33  # odd: the sun's centre is the middle pixel's centre


def sun_view(name):
    """The displayed (default view transform, suggested exposure) luminance of the disk's pixel and
    the largest of the aureole 2 pixels from it."""
    to_sun = (h.sun_lamps()[0].matrix_world.to_3x3() @ Vector((0, 0, 1))).normalized()
    sun_cam.rotation_euler = to_sun.to_track_quat("-Z", "Y").to_euler()
    h.render_settings(scene, res=(N, N), samples=4)
    vt.view_transform = default_vt
    scene.camera = sun_cam
    r = scene.render
    r.image_settings.file_format, r.image_settings.color_depth = "PNG", "16"
    r.filepath = os.path.join(h.OUT, name + ".png")
    bpy.ops.render.render(write_still=True)
    px = h.image_pixels(bpy.data.images.load(r.filepath, check_existing=False))
    c = N // 2
    disk = h.luminance(px[4 * (c * N + c):4 * (c * N + c) + 3])
    ring = max(h.luminance(px[4 * (y * N + x):4 * (y * N + x) + 3])
               for y in range(N) for x in range(N) if max(abs(x - c), abs(y - c)) == 2)
    return disk, ring


def card(name):
    h.render_settings(scene, res=(32, 32), samples=16)  # Standard, linear EXR: the light itself
    scene.camera = cam
    pix, w, hgt = h.render_linear(scene, os.path.join(h.OUT, name + ".exr"))
    return h.mean_luminance(pix, h.classify(scene, cam, w, hgt)["card"])


for preset in ("clear-noon", "hazy-desert"):
    bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset(preset))
    p = h.fast_settings(scene, width=1024)  # 0.35 deg pixels: the aureole resolved near the disk
    h.check(p.sun_mode == "LAMP" and p.camera_disk, "%s: the default Sun Lamp mode with the camera's disk" % preset)
    h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "%s: generate" % preset)
    h.check(bpy.ops.firmament_sky.apply_exposure() == {"FINISHED"}, "%s: apply the suggested exposure" % preset)
    disk, ring = sun_view("sun_" + preset)
    h.check(disk - ring >= MARGIN, "%s, %s at %.2f EV: the disk displays %.3f, the aureole 2 px from it at most %.3f "
            "(a margin of %.3f, at least %.2f)" % (preset, default_vt, vt.exposure, disk, ring, disk - ring, MARGIN))
    if preset == "hazy-desert":  # the roll-off acts here (the clear sky beside the sun is far below its knee)
        with_feature = card("card_" + preset)
        p.camera_disk = False
        h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "%s: generate without the camera's disk" % preset)
        without = card("card_plain_" + preset)
        h.close(with_feature / without, 1.0, 0.01, "%s: a white card is lit the same with the camera's disk and "
                "roll-off as without (%.5g vs %.5g)" % (preset, with_feature, without))
h.finish()

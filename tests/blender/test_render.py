"""Render the demo courtyard (Cycles CPU, tiny, denoising off) with a generated sky: sunlit ground
brighter than shaded ground by the sun's contribution, sky pixels equal to the map seen through the
world's mapping, plausible sky colour and exposure."""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

sys.path.insert(0, os.path.join(h.ROOT, "scenes"))
import demo_courtyard  # noqa: E402

h.install_and_enable()
scene = bpy.context.scene
cam = demo_courtyard.build(scene)
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset(os.environ.get("FIRMAMENT_TEST_PRESET", "clear-noon")))
p = h.fast_settings(scene, width=int(os.environ.get("FIRMAMENT_TEST_WIDTH", "256")))
p.apply_exposure = True
p.camera_disk = False  # the lamp alone first: the camera's view of the sun without any disk
p.north_offset = math.radians(float(os.environ.get("FIRMAMENT_TEST_NORTH", "0")))
h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate")
ev = scene.view_settings.exposure

W, H = int(os.environ.get("FIRMAMENT_TEST_RES_X", "96")), int(os.environ.get("FIRMAMENT_TEST_RES_Y", "64"))
r = scene.render
r.resolution_x, r.resolution_y, r.resolution_percentage = W, H, 100
scene.cycles.device = "CPU"
scene.cycles.samples = int(os.environ.get("FIRMAMENT_TEST_SAMPLES", "16"))
scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
scene.cycles.max_bounces = 4
scene.world.cycles.sample_map_resolution = 256
scene.view_settings.view_transform = "Standard"
r.image_settings.file_format = "PNG"
png = os.path.join(h.OUT, "courtyard.png")
r.filepath = png
bpy.ops.render.render(write_still=True)
# the linear result: Render Result saved as a float EXR (no view transform, no exposure)
exr = os.path.join(h.OUT, "courtyard.exr")
r.image_settings.file_format = "OPEN_EXR"
r.image_settings.color_depth = "32"
bpy.data.images["Render Result"].save_render(exr, scene=scene)
img = bpy.data.images.load(exr)
img.colorspace_settings.name = img.colorspace_settings.name  # float EXR: linear as rendered
px = h.image_pixels(img)
shown = bpy.data.images.load(png)
spx = h.image_pixels(shown)

# classify every pixel by ray casting the scene: sky, sunlit ground, shaded ground
depsgraph = bpy.context.evaluated_depsgraph_get()
frame = cam.data.view_frame(scene=scene)  # top-right, bottom-right, bottom-left, top-left (camera space)
tr, br, bl, tl = (Vector(v) for v in frame)
cam_rot = cam.matrix_world.to_3x3()
origin = cam.matrix_world.translation
lamp = h.sun_lamps()[0]
to_sun = (lamp.matrix_world.to_3x3() @ Vector((0, 0, 1))).normalized()
sky_dirs, lit, shade = [], [], []
for y in range(H):
    for x in range(W):
        fx, fy = (x + 0.5) / W, (y + 0.5) / H
        local = bl + fx * (br - bl) + fy * (tl - bl)
        d = (cam_rot @ local).normalized()
        hit, loc, normal, _i, obj, _m = scene.ray_cast(depsgraph, origin, d)
        k = 4 * (y * W + x)
        rgb = (px[k], px[k + 1], px[k + 2])
        if not hit:
            sky_dirs.append((d, rgb))
        elif obj.name == "Ground" and normal.z > 0.99:
            blocked = scene.ray_cast(depsgraph, loc + normal * 1e-3, to_sun)[0]
            (shade if blocked else lit).append((rgb, spx[k + 1]))

h.check(len(lit) > 50 and len(shade) > 50 and len(sky_dirs) > 50,
        "pixels: %d sunlit ground, %d shaded ground, %d sky" % (len(lit), len(shade), len(sky_dirs)))


def lum(c):
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


mean_lit = sum(lum(c) for c, _ in lit) / len(lit)
mean_shade = sum(lum(c) for c, _ in shade) / len(shade)
side = __import__("json").load(open(os.path.splitext(bpy.path.abspath(h.world_images()[0].filepath))[0] + ".json"))
e_dir = side["sun"]["direct_horizontal_illuminance_lux"] / 683.0  # Blender W/m^2
albedo = 0.35  # the paving's base colour
# a Lambertian ground: the sun adds albedo/pi x E_direct,horizontal to the sunlit pixels
expected = albedo / math.pi * e_dir
h.check(mean_lit > 1.5 * mean_shade, "sunlit ground brighter than shaded (%.3g vs %.3g)" % (mean_lit, mean_shade))
h.check(0.75 * expected < mean_lit - mean_shade < 1.3 * expected,
        "sunlit - shaded = the sun's albedo/pi x E_dir,h: %.3g vs %.3g" % (mean_lit - mean_shade, expected))

# sky pixels are the map looked up through the world's Mapping (nearest pixel, then the mean)
sky = [i for i in h.world_images()][0]
mp = h.image_pixels(sky)
mw, mh = sky.size
rot = p.north_offset  # the expected rotation (docs/output.md, "The map"), not the node's: orientation is under test
cz, sz = math.cos(rot), math.sin(rot)
total_render, total_map = [0.0] * 3, [0.0] * 3
for d, rgb in sky_dirs:
    v = Vector((cz * d.x - sz * d.y, sz * d.x + cz * d.y, d.z))  # Mapping: rotate the lookup
    u = 0.5 - math.atan2(v.y, v.x) / (2 * math.pi)
    t = 0.5 + math.asin(max(-1.0, min(1.0, v.z))) / math.pi
    xi, yi = min(mw - 1, int(u % 1.0 * mw)), min(mh - 1, int(t * mh))
    for c in range(3):
        total_render[c] += rgb[c]
        total_map[c] += mp[4 * (yi * mw + xi) + c]
n = len(sky_dirs)
mean_render = [t / n for t in total_render]
mean_map = [t / n for t in total_map]
for c in range(3):
    h.close(mean_render[c] / mean_map[c], 1.0, 0.08, "sky pixels = the map through the mapping, channel %d" % c)
h.check(mean_render[2] > mean_render[1] > mean_render[0], "clear sky is blue: mean rgb %.3g %.3g %.3g" % tuple(mean_render))
# exposure: the displayed (PNG, Standard view, suggested exposure) sunlit ground is mid-tone, not clipped
shown_lit = sum(s for _, s in lit) / len(lit)
h.check(0.3 < shown_lit < 0.95, "sunlit ground displays at %.2f with %.2f EV" % (shown_lit, ev))


# --- the sun is counted once in every mode: the same sunlit ground with the disk in the map (no
# lamp) and with lamp + camera-only disk; a camera aimed at the sun sees the disk only where it should
def render_linear(path, camera, res):
    scene.camera = camera
    r.resolution_x, r.resolution_y = res
    r.image_settings.file_format = "OPEN_EXR"
    r.filepath = path
    bpy.ops.render.render(write_still=True)
    im = bpy.data.images.load(path, check_existing=False)
    return h.image_pixels(im)


def mean_of(pixels, classified):
    return sum(lum(pixels[k:k + 3]) for k in classified) / len(classified)


# pixel indices of the sunlit ground, from the classification above
lit_idx = []
for y in range(H):
    for x in range(W):
        fx, fy = (x + 0.5) / W, (y + 0.5) / H
        d = (cam_rot @ (bl + fx * (br - bl) + fy * (tl - bl))).normalized()
        hit, loc, normal, _i, obj, _m = scene.ray_cast(depsgraph, origin, d)
        if hit and obj.name == "Ground" and normal.z > 0.99 and not scene.ray_cast(depsgraph, loc + normal * 1e-3, to_sun)[0]:
            lit_idx.append(4 * (y * W + x))
base = mean_of(px, lit_idx)
sun_cam_data = bpy.data.cameras.new("Sun camera")
sun_cam_data.lens = 200.0  # a narrow view: the disk covers a few pixels
sun_cam = bpy.data.objects.new("Sun camera", sun_cam_data)
scene.collection.objects.link(sun_cam)
sun_cam.location = cam.location
sun_cam.rotation_euler = to_sun.to_track_quat("-Z", "Y").to_euler()
scene.cycles.samples = 4
view_a = render_linear(os.path.join(h.OUT, "sun_view_lamp.exr"), sun_cam, (32, 32))
centre = 4 * (16 * 32 + 16)
peak_a = max(lum(view_a[k:k + 3]) for k in range(0, len(view_a), 4))
scene.cycles.samples = int(os.environ.get("FIRMAMENT_TEST_SAMPLES", "16"))
for mode in ("DISK", "LAMP_CAMERA_DISK"):
    p.sun_mode = mode
    h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate, sun mode %s" % mode)
    scene.world.cycles.sample_map_resolution = 512 if mode == "DISK" else 256
    shot = render_linear(os.path.join(h.OUT, "courtyard_%s.exr" % mode.lower()), cam, (W, H))
    h.close(mean_of(shot, lit_idx) / base, 1.0, 0.12,
            "sun mode %s: sunlit ground as with the lamp (sun counted once)" % mode)
    scene.cycles.samples = 4
    view = render_linear(os.path.join(h.OUT, "sun_view_%s.exr" % mode.lower()), sun_cam, (32, 32))
    scene.cycles.samples = int(os.environ.get("FIRMAMENT_TEST_SAMPLES", "16"))
    peak = max(lum(view[k:k + 3]) for k in range(0, len(view), 4))
    at = max(range(0, len(view), 4), key=lambda k: lum(view[k:k + 3])) // 4
    h.check(peak > 20 * peak_a and abs(at % 32 - 16) <= 2 and abs(at // 32 - 16) <= 2,
            "sun mode %s: the camera sees the disk at the lamp's direction (peak %.3g at %d,%d; %.3g without)"
            % (mode, peak, at % 32, at // 32, peak_a))
# the default Sun Lamp mode with the camera-only disk: the camera sees a disk as bright as the map's,
# the sunlit ground is lit as with the lamp alone (the disk adds no light)
p.sun_mode, p.camera_disk = "LAMP", True
h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate, sun lamp + camera-only disk")
scene.world.cycles.sample_map_resolution = 256
shot = render_linear(os.path.join(h.OUT, "courtyard_camera_disk.exr"), cam, (W, H))
h.close(mean_of(shot, lit_idx) / base, 1.0, 0.05, "camera-only disk: sunlit ground as with the lamp alone")
scene.cycles.samples = 4
view = render_linear(os.path.join(h.OUT, "sun_view_camera_disk.exr"), sun_cam, (32, 32))
peak = max(lum(view[k:k + 3]) for k in range(0, len(view), 4))
at = max(range(0, len(view), 4), key=lambda k: lum(view[k:k + 3])) // 4
sun_light = h.sun_lamps()[0].data
disk_l = lum([sun_light.energy * c for c in sun_light.color]) / (2 * math.pi * (1 - math.cos(sun_light.angle / 2)))
h.check(0.5 < peak / disk_l < 1.05 and abs(at % 32 - 16) <= 2 and abs(at // 32 - 16) <= 2,
        "camera-only disk at the lamp's direction with the sun's radiance, DNI / disk solid angle "
        "(peak %.3g vs %.3g at %d,%d; a pixel is 0.32 deg, the disk 0.52)" % (peak, disk_l, at % 32, at // 32))
# displayed at the suggested exposure through Blender's default view transform (Filmic, AgX from 4.0),
# the disk stands out of the aureole beside it (2 pixels, 0.64 deg, from its centre): not clipped into it
vt = scene.view_settings
vt.view_transform = "AgX" if "AgX" in [i.identifier for i in vt.bl_rna.properties["view_transform"].enum_items] else "Filmic"
scene.camera = sun_cam
r.resolution_x, r.resolution_y = 32, 32
r.image_settings.file_format, r.image_settings.color_depth = "PNG", "16"
r.filepath = os.path.join(h.OUT, "sun_view_displayed.png")
bpy.ops.render.render(write_still=True)
shown = h.image_pixels(bpy.data.images.load(r.filepath, check_existing=False))
disk_shown = lum(shown[4 * at:4 * at + 3])
ring = [lum(shown[4 * (y * 32 + x):4 * (y * 32 + x) + 3]) for y in range(32) for x in range(32)
        if max(abs(x - at % 32), abs(y - at // 32)) == 2]
h.check(disk_shown > max(ring) + 0.02, "%s at %.2f EV: the disk displays above the aureole beside it (%.3f vs at most %.3f)"
        % (vt.view_transform, vt.exposure, disk_shown, max(ring)))
h.finish()

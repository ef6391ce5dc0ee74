"""Install the zip, enable it, pick a shipped preset, Generate through the real executable; check
the world's node tree, the image, the lamp against the sidecar, and that the sun is not doubled."""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

h.install_and_enable()
scene = bpy.context.scene
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("shadow-study-45"))
p = h.fast_settings(scene)
h.check(p.sun_source == "ANGLES" and p.sun_elevation == 45 and p.biome == "rural", "preset loaded")
world_before = scene.world


def sidecar_of(img):
    return json.load(open(os.path.splitext(bpy.path.abspath(img.filepath))[0] + ".json"))


def pixel_direction(x, y, w, hgt, rotation_z):
    """Blender's equirect lookup inverted (u = 0.5 - atan2(y, x)/2pi, v = 0.5 + elevation/pi), then
    the Mapping rotation undone: the scene direction that sees pixel (x, y), rows bottom-up."""
    u, v = (x + 0.5) / w, (y + 0.5) / hgt
    phi = (0.5 - u) * 2 * math.pi
    el = (v - 0.5) * math.pi
    d = Vector((math.cos(el) * math.cos(phi), math.cos(el) * math.sin(phi), math.sin(el)))
    c, s = math.cos(-rotation_z), math.sin(-rotation_z)
    return Vector((c * d.x - s * d.y, s * d.x + c * d.y, d.z))


def map_checks(mode_label, north_offset_deg):
    img = h.world_images()
    h.check(len(img) == (2 if p.sun_mode == "LAMP_CAMERA_DISK" else 1), "%s: images of the sky: %d" % (mode_label, len(img)))
    sky = [i for i in img if i.name.startswith("Firmament Sky") and "Disk" not in i.name][0]
    h.check(sky.is_float, "%s: float image" % mode_label)
    h.check(sky.colorspace_settings.name in ("Linear Rec.709", "Linear"),
            "%s: colour space %s" % (mode_label, sky.colorspace_settings.name))
    h.check(tuple(sky.size) == (128, 64), "%s: size %s" % (mode_label, tuple(sky.size)))
    side = sidecar_of(sky)
    nodes = scene.world.node_tree.nodes
    out = [n for n in nodes if n.type == "OUTPUT_WORLD" and n.is_active_output][0]
    # Texture Coordinate -> Mapping -> Environment -> Background (-> Mix) -> Output
    link = out.inputs["Surface"].links[0]
    first = link.from_node
    if p.sun_mode == "LAMP_CAMERA_DISK":
        h.check(first.type == "MIX_SHADER", "%s: output fed by a mix shader" % mode_label)
        fac = first.inputs["Fac"].links[0]
        h.check(fac.from_node.type == "LIGHT_PATH" and fac.from_socket.name == "Is Camera Ray",
                "%s: mix by Is Camera Ray" % mode_label)
        bg_sky = first.inputs[1].links[0].from_node
        bg_disk = first.inputs[2].links[0].from_node
        env_disk = bg_disk.inputs["Color"].links[0].from_node
        h.check(env_disk.image.name.endswith("With Disk") and sidecar_of(env_disk.image)["image"]["contains_sun_disk"],
                "%s: camera rays see the map with the disk" % mode_label)
    else:
        bg_sky = first
    h.check(bg_sky.type == "BACKGROUND" and abs(bg_sky.inputs["Strength"].default_value - 1.0) < 1e-9,
            "%s: background strength 1" % mode_label)
    env = h.env_of(bg_sky)
    h.check(env.type == "TEX_ENVIRONMENT" and env.image == sky, "%s: environment texture holds the map" % mode_label)
    mapping = env.inputs["Vector"].links[0].from_node
    h.check(mapping.type == "MAPPING" and mapping.vector_type == "POINT", "%s: mapping node" % mode_label)
    tc = mapping.inputs["Vector"].links[0]
    h.check(tc.from_node.type == "TEX_COORD" and tc.from_socket.name == "Generated", "%s: generated coordinates" % mode_label)
    rot = tuple(mapping.inputs["Rotation"].default_value)
    h.close(math.degrees(rot[2]), north_offset_deg, 1e-4, "%s: mapping rotation Z = north offset" % mode_label)

    lamps = h.sun_lamps()
    rgb = side["sun"]["direct_normal_irradiance_rgb"]
    if p.sun_mode == "DISK":
        h.check(len(lamps) == 0, "%s: no lamp when the disk is in the map" % mode_label)
        h.check(side["image"]["contains_sun_disk"], "%s: map holds the disk" % mode_label)
    else:
        h.check(len(lamps) == 1, "%s: one sun lamp (%d)" % (mode_label, len(lamps)))
        lamp = lamps[0]
        h.check(not side["image"]["contains_sun_disk"], "%s: lighting map has no disk (sidecar)" % mode_label)
        # direction: lamp's +Z (it shines along -Z) against the sidecar's, rotated by the north offset
        nu = math.radians(north_offset_deg)
        d = Vector(side["sun"]["direction"])
        want = Vector((math.cos(-nu) * d.x - math.sin(-nu) * d.y, math.sin(-nu) * d.x + math.cos(-nu) * d.y, d.z))
        got = lamp.matrix_world.to_3x3() @ Vector((0, 0, 1))
        ang = math.degrees(got.angle(want))
        h.check(ang < 0.1, "%s: lamp direction within 0.1 deg of the sidecar's (%.4f deg)" % (mode_label, ang))
        # the sun's compass elevation and azimuth as seen in the scene
        el = math.degrees(math.asin(got.z))
        az = math.degrees(math.atan2(got.x, got.y)) % 360
        h.close(el, side["sun"]["elevation_deg"], 0.1, "%s: lamp elevation" % mode_label)
        h.close((az - north_offset_deg) % 360, side["sun"]["azimuth_deg"] % 360, 0.1, "%s: lamp azimuth - offset" % mode_label)
        strength = [lamp.data.energy * c for c in lamp.data.color]
        for c in range(3):
            h.close(strength[c], rgb[c], 1e-4 * rgb[c], "%s: lamp strength x colour [%d] = sidecar irradiance" % (mode_label, c))
        h.close(math.degrees(lamp.data.angle), side["sun"]["angular_diameter_deg"], 1e-4, "%s: lamp angle" % mode_label)

    # the disk's energy: no pixel of the lighting map carries it; the disk map's brightest pixel sits at the sun
    px = h.image_pixels(sky)
    w, hgt = sky.size
    dni = max(rgb)
    best, best_xy = -1.0, (0, 0)
    for y in range(hgt):
        el = (y + 0.5) / hgt * math.pi - math.pi / 2
        omega = (2 * math.pi / w) * (math.pi / hgt) * math.cos(el)  # pixel solid angle
        for x in range(w):
            e = px[4 * (y * w + x)] * omega
            if e > best:
                best, best_xy = e, (x, y)
    if side["image"]["contains_sun_disk"]:
        h.check(best > 0.2 * dni, "%s: the map's brightest pixel carries the disk (%.3g of %.3g)" % (mode_label, best, dni))
        d = pixel_direction(best_xy[0], best_xy[1], w, hgt, rot[2])
        sun_dir = Vector(side["sun"]["direction"])
        nu = math.radians(north_offset_deg)
        sun_scene = Vector((math.cos(-nu) * sun_dir.x - math.sin(-nu) * sun_dir.y,
                            math.sin(-nu) * sun_dir.x + math.cos(-nu) * sun_dir.y, sun_dir.z))
        ang = math.degrees(d.angle(sun_scene))
        h.check(ang < 3.0, "%s: the disk appears where the sun is in the scene (%.2f deg, pixel 2.8 deg)" % (mode_label, ang))
    else:
        h.check(best < 0.02 * dni, "%s: no pixel holds the disk's energy (max %.3g vs DNI %.3g)" % (mode_label, best, dni))


# mode (a), the default
h.check(p.sun_mode == "LAMP", "default sun mode is the lamp")
h.check(not p.apply_exposure and p.metering == "HORIZONTAL", "Set Exposure is off by default; metering: horizontal card")
p.apply_exposure = True
res = bpy.ops.firmament_sky.generate()
h.check(res == {"FINISHED"}, "generate finished")
h.check(scene.world is world_before, "the scene's world is reused")
map_checks("lamp", 0.0)
h.check(abs(scene.view_settings.exposure - p.suggested_exposure_ev) < 1e-6 and -7 < p.suggested_exposure_ev < -4,
        "suggested exposure applied: %.2f EV" % scene.view_settings.exposure)

# north offset 30 degrees, same mode: re-generation replaces (one image, one lamp)
p.north_offset = math.radians(30.0)
bpy.ops.firmament_sky.generate()
map_checks("lamp, north offset 30", 30.0)
h.check(len([n for n in scene.world.node_tree.nodes if n.type == "TEX_ENVIRONMENT"]) == 1, "one environment node")

# mode (b): the disk in the map, no lamp
p.sun_mode = "DISK"
bpy.ops.firmament_sky.generate()
map_checks("disk", 30.0)

# mode (c): lamp + disk for camera rays only
p.sun_mode = "LAMP_CAMERA_DISK"
bpy.ops.firmament_sky.generate()
map_checks("lamp + camera disk", 30.0)

# back to (a): nothing piles up
p.sun_mode = "LAMP"
p.north_offset = 0.0
bpy.ops.firmament_sky.generate()
map_checks("lamp again", 0.0)
h.check(len(h.world_images()) == 1 and len(h.sun_lamps()) == 1, "re-generation leaves one image and one lamp")
h.check(h.world_images()[0].name == "Firmament Sky", "the image keeps its name (%s)" % h.world_images()[0].name)
# a renamed lamp is still the add-on's: re-generating updates it instead of adding another
h.sun_lamps()[0].name = "My Sun"
bpy.ops.firmament_sky.generate()
h.check([o.name for o in h.sun_lamps()] == ["My Sun"], "a renamed lamp is reused: %s" % [o.name for o in h.sun_lamps()])
h.check(len([l for l in bpy.data.lights if l.name.startswith("Firmament")]) == 1, "one Firmament light datablock")
nodes = scene.world.node_tree.nodes
h.check(len([n for n in nodes if n.name.startswith("Firmament")]) == 19,
        "19 Firmament nodes: five the camera's disk, ten its highlight roll-off (%d)" %
        len([n for n in nodes if n.name.startswith("Firmament")]))
# a sun below the horizon: the lamp is hidden, not a 0 W lamp shining up through the ground
p.sun_source, p.sun_elevation = "ANGLES", -4.0
bpy.ops.firmament_sky.generate()
h.check(len(h.sun_lamps()) == 1 and h.sun_lamps()[0].hide_render and h.sun_lamps()[0].hide_viewport,
        "sun 4 deg below the horizon: the lamp is hidden")
p.sun_elevation = 45.0
bpy.ops.firmament_sky.generate()
h.check(not h.sun_lamps()[0].hide_render, "sun up again: the lamp shows")

# metering: a horizontal card makes every sky equally bright; the sky average keeps a low sun darker
world_mod = sys.modules["firmament_sky.world"]
cards = {}
for name in ("clear-noon", "golden-hour"):
    bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset(name))
    h.fast_settings(scene, width=32)
    bpy.ops.firmament_sky.generate()
    sun = world_mod.read_sidecar(os.path.splitext(bpy.path.abspath(h.world_images()[0].filepath))[0] + ".json")
    card = sun["global_lux"] / 683.0 / math.pi  # a white horizontal card's luminance, Blender units
    cards[name] = {m: card * 2 ** world_mod.metered_exposure(sun, m) for m in ("HORIZONTAL", "SKY")}
h.close(cards["golden-hour"]["HORIZONTAL"], 1.0, 1e-6, "horizontal-card metering: the card shows as 1.0")
h.check(cards["golden-hour"]["SKY"] < cards["clear-noon"]["SKY"],
        "sky-average metering: the golden-hour card darker than noon's (%.2f vs %.2f)"
        % (cards["golden-hour"]["SKY"], cards["clear-noon"]["SKY"]))

# Generate deletes no map (a saved file may use it); Clean Unused Maps keeps only the one in use
from firmament_sky import maps  # noqa: E402
folders = os.listdir(maps.cache_dir())
h.check(len(folders) == 10, "every generated map is still in the cache (%d)" % len(folders))
bpy.ops.firmament_sky.clean_maps()
folders = os.listdir(maps.cache_dir())
h.check(folders == [os.path.basename(os.path.dirname(bpy.path.abspath(h.world_images()[0].filepath)))],
        "Clean Unused Maps leaves the map in use (%d folders)" % len(folders))

# The panel's AOD 550 and visibility before Generate are the sidecar's after it
import time  # noqa: E402
panels = h.submodule("panels")
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("shadow-study-45"))
p = h.fast_settings(scene, width=32)
p.aerosol_amount = "TURBIDITY"
for turbidity in (1.0, 3.0):
    p.turbidity = turbidity
    t0 = time.perf_counter()
    shown = panels.aerosol_summary(p, bpy.context)
    print("panel's aerosol figures for turbidity %g: %s in %.1f ms" % (turbidity, shown, 1e3 * (time.perf_counter() - t0)))
    bpy.ops.firmament_sky.generate()
    atm = h.sidecar_of(h.sky_image())["atmosphere"]
    h.check(shown is not None, "turbidity %g: the panel shows AOD and visibility" % turbidity)
    if shown:
        h.close(shown[0], atm["aerosol_optical_depth_550nm"], 1e-6, "turbidity %g: panel's AOD 550" % turbidity)
        h.close(shown[1], atm["visibility_km"], 1e-3, "turbidity %g: panel's visibility km" % turbidity)
h.finish()

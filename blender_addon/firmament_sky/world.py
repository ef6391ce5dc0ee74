"""World and sun setup from a rendered map and its sidecar.  Everything that can fail (reading
the sidecar, loading the images) happens before the world is touched, so a failure leaves the
previous world as it was.  What the add-on creates is tagged (images and the lamp carry the custom
property "firmament_sky", nodes are named "Firmament ...") so that re-generating replaces it."""

import json
import math

import bpy
from mathutils import Color, Vector

TAG = "firmament_sky"
NODE_PREFIX = "Firmament "
LAMP_NAME = "Firmament Sun"
# Blender 4.x calls the space "Linear Rec.709"; 3.x "Linear" (same primaries, D65).
COLORSPACE_NAMES = ("Linear Rec.709", "Linear")


class SetupError(RuntimeError):
    pass


def read_sidecar(path):
    try:
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
    except (OSError, ValueError) as e:
        raise SetupError("cannot read the sidecar %s: %s" % (path, e)) from None
    return sidecar_fields(d, path)


def sidecar_fields(d, where):
    """What the add-on uses of a sidecar's dict (a file's, or a `firmament serve` reply's)."""
    try:
        sun, image = d["sun"], d["image"]
        out = {
            "direction": [float(x) for x in sun["direction"]],
            "angular_diameter_deg": float(sun["angular_diameter_deg"]),
            "irradiance_rgb": [float(x) for x in sun["direct_normal_irradiance_rgb"]],
            "elevation_deg": float(sun["elevation_deg"]),
            "azimuth_deg": float(sun["azimuth_deg"]),
            "contains_sun_disk": bool(image["contains_sun_disk"]),
            "azimuth_at_center_deg": float(image.get("azimuth_at_center_deg", 90.0)),
            "suggested_exposure_ev": d.get("sky", {}).get("suggested_exposure_ev"),
            "global_lux": d.get("sky", {}).get("global_horizontal_illuminance_lux"),
            "diffuse_lux": d.get("sky", {}).get("diffuse_horizontal_illuminance_lux"),
            "dni_lux": sun.get("direct_normal_illuminance_lux"),
            "aod550": d.get("atmosphere", {}).get("aerosol_optical_depth_550nm"),
            "cloud_transmittance": float(sun.get("cloud_direct_transmittance_550nm", 1.0)),
        }
    except (ValueError, KeyError, TypeError) as e:
        raise SetupError("cannot read the sidecar %s: %s" % (where, e)) from None
    if len(out["direction"]) != 3 or len(out["irradiance_rgb"]) != 3:
        raise SetupError("sidecar %s: sun.direction and sun.direct_normal_irradiance_rgb need 3 values" % where)
    return out


def load_float_image(path, name):
    """The EXR as a float image in linear Rec.709; raises SetupError (nothing left behind)."""
    try:
        img = bpy.data.images.load(path, check_existing=False)
    except RuntimeError as e:
        raise SetupError("cannot load %s: %s" % (path, e)) from None
    img.name = name
    img[TAG] = 1
    for cs in COLORSPACE_NAMES:
        try:
            img.colorspace_settings.name = cs
            break
        except TypeError:
            continue
    else:
        bpy.data.images.remove(img)
        raise SetupError("no linear Rec.709 colour space (tried %s) in this Blender's OCIO config"
                         % ", ".join(COLORSPACE_NAMES))
    if not img.is_float or img.size[0] == 0:
        bpy.data.images.remove(img)
        raise SetupError("%s did not load as a float image" % path)
    return img


def scene_direction(direction, north_offset):
    """A sky direction (+X east, +Y north, +Z up) in the scene: compass azimuth A appears at scene
    azimuth A + north_offset (clockwise seen from above), i.e. a rotation by -north_offset about Z."""
    c, s = math.cos(-north_offset), math.sin(-north_offset)
    x, y, z = direction
    return Vector((c * x - s * y, s * x + c * y, z)).normalized()


def mapping_rotation_z(north_offset, azimuth_at_center_deg=90.0):
    """The Mapping node's Z rotation: scene direction v looks up sky direction Rz(theta) v, so theta =
    north_offset puts the sky's direction d at Rz(-north_offset) d; a map centred on another azimuth
    than east (Blender's layout) adds A0 - 90 degrees."""
    return north_offset + math.radians(azimuth_at_center_deg - 90.0)


def our_images():
    return [img for img in bpy.data.images if img.get(TAG)]


def _our_lamps():
    """The add-on's lamp objects, found by their tag (the user may have renamed them)."""
    return [o for o in bpy.data.objects if o.get(TAG) and o.type == "LIGHT"]


def _remove_lamp(keep=None):
    for obj in _our_lamps():
        if obj is keep:
            continue
        light = obj.data
        bpy.data.objects.remove(obj)
        if light is not None and light.users == 0:
            bpy.data.lights.remove(light)


def _ensure_lamp(scene):
    lamps = [o for o in _our_lamps() if o.data.type == "SUN"]
    obj = lamps[0] if lamps else None
    _remove_lamp(keep=obj)  # never more than one
    if obj is None:
        light = bpy.data.lights.new(LAMP_NAME, type="SUN")
        obj = bpy.data.objects.new(LAMP_NAME, light)
        obj[TAG] = 1
    if obj.name not in scene.collection.objects and not any(obj.name in c.objects for c in scene.collection.children_recursive):
        scene.collection.objects.link(obj)
    return obj


def _world_output(nodes):
    for n in nodes:
        if n.type == "OUTPUT_WORLD" and n.is_active_output:
            return n
    for n in nodes:
        if n.type == "OUTPUT_WORLD":
            return n
    return nodes.new("ShaderNodeOutputWorld")


def _env_node(nodes, links, mapping, image, name, x, y):
    env = nodes.new("ShaderNodeTexEnvironment")
    env.name = env.label = NODE_PREFIX + name
    env.image = image
    env.interpolation = "Linear"
    env.location = (x, y)
    links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    bg = nodes.new("ShaderNodeBackground")
    bg.name = bg.label = NODE_PREFIX + name + " Background"
    bg.inputs["Strength"].default_value = 1.0  # pixel values are radiance: 1:1 with the lamp (x Sky Strength)
    bg.location = (x + 300, y)
    links.new(env.outputs["Color"], bg.inputs["Color"])
    return bg


def build_world_nodes(world, sky_image, disk_image, rotation_z, settings=None, sun=None):
    if world.node_tree is None:  # before 5.0 a new world has no tree until use_nodes (deprecated in 5.0)
        world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    for n in [n for n in nodes if n.name.startswith(NODE_PREFIX)]:
        nodes.remove(n)
    out = _world_output(nodes)
    out.location = (900, 300)
    coords = nodes.new("ShaderNodeTexCoord")
    coords.name = coords.label = NODE_PREFIX + "Coordinates"
    coords.location = (-500, 300)
    mapping = nodes.new("ShaderNodeMapping")
    mapping.name = mapping.label = NODE_PREFIX + "North"
    mapping.vector_type = "POINT"
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, rotation_z)
    mapping.location = (-300, 300)
    links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    sky_bg = _env_node(nodes, links, mapping, sky_image, "Sky", 0, 300)
    settings = settings or {}
    sky_bg.inputs["Strength"].default_value = settings.get("sky_strength", 1.0)
    if settings.get("ground", "MAP") != "MAP":
        _ground_nodes(nodes, links, mapping, sky_bg, settings, sun)
    if settings.get("sun_mode") == "LAMP" and settings.get("camera_disk") and sun and \
            sun["elevation_deg"] + sun["angular_diameter_deg"] / 2 >= 0.0:
        _camera_rolloff_nodes(nodes, links, sky_bg, settings, sun)  # before the disk: the disk stays whole
        _camera_disk_nodes(nodes, links, mapping, sky_bg, settings, sun)
    if disk_image is None:
        links.new(sky_bg.outputs["Background"], out.inputs["Surface"])
        return
    # camera rays see the map with the disk; every other ray the one without (the lamp lights)
    disk_bg = _env_node(nodes, links, mapping, disk_image, "Sky With Disk", 0, 0)
    disk_bg.inputs["Strength"].default_value = settings.get("sky_strength", 1.0)
    path = nodes.new("ShaderNodeLightPath")
    path.name = path.label = NODE_PREFIX + "Light Path"
    path.location = (300, 600)
    mix = nodes.new("ShaderNodeMixShader")
    mix.name = mix.label = NODE_PREFIX + "Camera Sees Disk"
    mix.location = (650, 300)
    links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    links.new(sky_bg.outputs["Background"], mix.inputs[1])
    links.new(disk_bg.outputs["Background"], mix.inputs[2])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])


def _clear_animation(obj):
    for idb in (obj, obj.data):
        if idb.animation_data is not None:
            idb.animation_data_clear()


def _mix_into(nodes, links, bg, name, factor, rgb, location):
    """Between the Background's colour and what feeds it: where factor is 1, the colour rgb."""
    source = bg.inputs["Color"].links[0].from_socket
    mix = _node(nodes, "ShaderNodeMix", name, location, data_type="RGBA")
    fac = [i for i in mix.inputs if i.name == "Factor" and i.type == "VALUE"][0]
    a, b = [i for i in mix.inputs if i.type == "RGBA"][:2]
    links.new(factor, fac)
    links.new(source, a)
    b.default_value = (rgb[0], rgb[1], rgb[2], 1.0)
    links.new([o for o in mix.outputs if o.type == "RGBA"][0], bg.inputs["Color"])


def _node(nodes, kind, name, location, **attrs):
    n = nodes.new(kind)
    n.name = n.label = NODE_PREFIX + name
    n.location = location
    for k, v in attrs.items():
        setattr(n, k, v)
    return n


def _ground_nodes(nodes, links, mapping, bg, settings, sun):
    """Below the horizon (the looked-up direction's z < 0) the world shows a chosen ground instead of
    the map's: black, or a Lambertian ground of the given reflectance under this sky (radiance
    reflectance x global horizontal illuminance / (683 pi), in Blender's units)."""
    sep = _node(nodes, "ShaderNodeSeparateXYZ", "Direction", (-100, 600))
    links.new(mapping.outputs["Vector"], sep.inputs["Vector"])
    below = _node(nodes, "ShaderNodeMath", "Below Horizon", (100, 600), operation="LESS_THAN")
    below.inputs[1].default_value = 0.0
    links.new(sep.outputs["Z"], below.inputs[0])
    lum = (sun or {}).get("global_lux") or 0.0
    k = lum / (683.0 * math.pi) if settings["ground"] == "COLOUR" else 0.0
    rgb = Color(settings.get("ground_colour", (0.0, 0.0, 0.0)))
    _mix_into(nodes, links, bg, "Ground", below.outputs["Value"], [c * k for c in rgb], (250, 450))


# The camera's highlight roll-off, in scene-linear values after the suggested exposure: Filmic and AgX
# (the default view transforms) reach white at 0.18 x 2^6.5 = 16.3, so an aureole above that clips
# to the disk's white.  Above the knee, a luminance x stops over it shows as S (1 - e^(-x/S)) stops
# (slope 1 at the knee, never more than S stops over it): at most 2.5 x 2^1.2 = 5.7, which Filmic
# shows at 0.93 and AgX at 0.87 of white, below the disk (about 3e4: white in any transform).
ROLLOFF_KNEE = 2.5
ROLLOFF_STOPS = 1.2


def _math(nodes, links, name, location, operation, a, b=None, c=None):
    """A Math node; its inputs are sockets (linked) or numbers."""
    m = _node(nodes, "ShaderNodeMath", name, location, operation=operation)
    for i, v in enumerate((a, b, c)):
        if v is None:
            continue
        if isinstance(v, (int, float)):
            m.inputs[i].default_value = v
        else:
            links.new(v, m.inputs[i])
    return m.outputs["Value"]


def _camera_rolloff_nodes(nodes, links, bg, settings, sun):
    """For camera rays only, the world's highlights above the knee rolled off (hue kept: the colour
    scaled by the luminance's ratio), so that at the suggested exposure the aureole stays below white
    and the camera's sun disk stands out of it.  Every other ray (lighting, reflections) sees the map
    as it is.  Nothing is added without an exposure to key it to (night)."""
    ev = metered_exposure(sun, settings.get("metering", "HORIZONTAL"))
    if ev is None:
        return
    knee = ROLLOFF_KNEE * 2.0 ** -ev / max(settings.get("sky_strength", 1.0), 1e-6)  # in the map's values
    source = bg.inputs["Color"].links[0].from_socket
    lum = _node(nodes, "ShaderNodeRGBToBW", "Luminance", (-100, 1200))
    links.new(source, lum.inputs["Color"])
    above = _math(nodes, links, "Over Knee", (50, 1200), "MAXIMUM", lum.outputs["Val"], knee)
    x = _math(nodes, links, "Stops Over Knee", (200, 1200), "LOGARITHM", _math(
        nodes, links, "Ratio to Knee", (100, 1350), "DIVIDE", above, knee), 2.0)
    fall = _math(nodes, links, "Shoulder", (350, 1200), "EXPONENT",
                 _math(nodes, links, "Shoulder Rate", (250, 1350), "MULTIPLY", x, -1.0 / ROLLOFF_STOPS))
    shown = _math(nodes, links, "Stops Shown", (500, 1200), "MULTIPLY_ADD", fall, -ROLLOFF_STOPS, ROLLOFF_STOPS)
    scale = _math(nodes, links, "Roll-off", (650, 1200), "POWER", 2.0,
                  _math(nodes, links, "Stops Removed", (550, 1350), "SUBTRACT", shown, x))
    path = _node(nodes, "ShaderNodeLightPath", "Camera Path", (100, 1000))  # the disk's nodes use it too
    mix = _node(nodes, "ShaderNodeMix", "Camera Roll-off", (800, 1200), data_type="RGBA", blend_type="MULTIPLY")
    fac = [i for i in mix.inputs if i.name == "Factor" and i.type == "VALUE"][0]
    a, b = [i for i in mix.inputs if i.type == "RGBA"][:2]
    links.new(path.outputs["Is Camera Ray"], fac)
    links.new(source, a)
    links.new(scale, b)
    links.new([o for o in mix.outputs if o.type == "RGBA"][0], bg.inputs["Color"])


def _camera_disk_nodes(nodes, links, mapping, bg, settings, sun):
    """The sun disk for camera rays only (the lamp lights; nothing is counted twice): a uniform
    disk of the sun's angular size and its radiance, the direct normal irradiance / the disk's solid
    angle, where the looked-up direction is within the sun's radius."""
    radius = math.radians(sun["angular_diameter_deg"]) / 2
    solid_angle = 2 * math.pi * (1 - math.cos(radius))
    dot = _node(nodes, "ShaderNodeVectorMath", "Toward Sun", (-100, 800), operation="DOT_PRODUCT")
    links.new(mapping.outputs["Vector"], dot.inputs[0])
    dot.inputs[1].default_value = sun["direction"]  # the map's frame: the mapping's output
    inside = _node(nodes, "ShaderNodeMath", "In Sun Disk", (100, 800), operation="GREATER_THAN")
    inside.inputs[1].default_value = math.cos(radius)
    links.new(dot.outputs["Value"], inside.inputs[0])
    path = nodes.get(NODE_PREFIX + "Camera Path") or _node(nodes, "ShaderNodeLightPath", "Camera Path", (100, 1000))
    camera = _node(nodes, "ShaderNodeMath", "Camera Sees Sun", (250, 900), operation="MULTIPLY")
    links.new(inside.outputs["Value"], camera.inputs[0])
    links.new(path.outputs["Is Camera Ray"], camera.inputs[1])
    scale = settings.get("sun_strength", 1.0) / max(settings.get("sky_strength", 1.0), 1e-6) / solid_angle
    rgb = Color(sun["irradiance_rgb"]).from_rec709_linear_to_scene_linear()
    _mix_into(nodes, links, bg, "Sun Disk", camera.outputs["Value"], [c * scale for c in rgb], (450, 600))


def _scene_bounds(scene):
    """(centre, radius) of a sphere around the scene's meshes (origin and 8 m when it has none)."""
    corners = [o.matrix_world @ Vector(c) for o in scene.objects if o.type == "MESH" for c in o.bound_box]
    if not corners:
        return Vector((0.0, 0.0, 0.0)), 8.0
    lo = Vector([min(c[i] for c in corners) for i in range(3)])
    hi = Vector([max(c[i] for c in corners) for i in range(3)])
    return (lo + hi) / 2, (hi - lo).length / 2


# Clouds that leave less than this of the direct beam (at 550 nm) switch the lamp off: its strength
# is already nothing (a millionth of the sun's, 0.1 lux at most) and the sky carries the light.
HIDDEN_BY_CLOUDS = 1e-6
CLOUD_KEY = "firmament_cloud_transmittance"  # the lamp's custom property: its last sidecar's, at 550 nm


def setup_lamp(scene, sun, north_offset, strength=1.0):
    """Points, sizes and colours the add-on's lamp for one sidecar; a sun whose disk is wholly below
    the horizon, or hidden by clouds, hides it (no lamp shining up through the ground or a deck)."""
    obj = _ensure_lamp(scene)
    light = obj.data
    sun = dict(sun, strength=strength)
    # strength x colour = the direct normal irradiance, in the map's units (Blender W/m^2), converted
    # from the map's linear Rec.709 to the scene's working space (5.0: Rec.2020 or ACEScg) the way
    # Blender converts the map tagged Linear Rec.709
    rgb = list(Color(sun["irradiance_rgb"]).from_rec709_linear_to_scene_linear())
    peak = max(rgb)
    light.energy = max(peak, 0.0) * sun.get("strength", 1.0)
    light.color = [c / peak for c in rgb] if peak > 0.0 else (1.0, 1.0, 1.0)
    light.angle = math.radians(sun["angular_diameter_deg"])
    obj[CLOUD_KEY] = sun.get("cloud_transmittance", 1.0)
    point_lamp(scene, sun["direction"], north_offset,
               sun["elevation_deg"] + sun["angular_diameter_deg"] / 2 < 0.0 or peak <= 0.0)
    return obj


def point_lamp(scene, direction, north_offset, below, cloudless=False):
    """Turns the add-on's lamp toward the sky direction (+X east, +Y north, +Z up) and hides it when
    below (the sun's disk is under the horizon: no light up through the ground) or when the clouds
    of its last sidecar hid the sun, unless cloudless (no cloud layer, no fog): a sun moved before
    its map arrives keeps its deck's verdict instead of flashing on until the map hides it."""
    obj = _ensure_lamp(scene)
    d = scene_direction(direction, north_offset)
    obj.rotation_mode = "XYZ"
    obj.rotation_euler = d.to_track_quat("Z", "Y").to_euler()  # the lamp shines along its -Z
    centre, radius = _scene_bounds(scene)
    obj.location = centre + d * (radius + 2.0)  # only for the viewport: outside the scene, toward the sun
    hidden = below or (not cloudless and obj.get(CLOUD_KEY, 1.0) < HIDDEN_BY_CLOUDS)
    if obj.hide_viewport != hidden or obj.hide_render != hidden:  # each set re-syncs the scene's collections
        obj.hide_render = obj.hide_viewport = hidden
    return obj


def _replace_images(previous, names):
    """Removes the previous maps' images from the file (never their files) and gives the new ones
    the names the old ones had."""
    for img in previous:
        bpy.data.images.remove(img)
    for img, name in names:
        img.name = name


def metered_exposure(sun, metering):
    """The film exposure (EV) that makes the metered quantity look right, or None (night): a white
    Lambertian card under illuminance E (lux) shows E / (683 pi) in Blender's units, made 1.0 for
    the cards; the sky's cosine-weighted average luminance (diffuse E / pi) is made 0.18."""
    lux = {"HORIZONTAL": sun["global_lux"], "SUN_FACING": (sun["dni_lux"] or 0.0) + (sun["diffuse_lux"] or 0.0),
           "SKY": sun["diffuse_lux"]}[metering]
    if not lux or lux <= 0.0:
        return None
    level = 0.18 if metering == "SKY" else 1.0
    return math.log2(level * 683.0 * math.pi / lux)


def _set_exposure(scene, settings, sun, frame=None):
    if not settings.get("apply_exposure"):
        return None
    ev = metered_exposure(sun, settings.get("metering", "HORIZONTAL"))
    if ev is None:
        return None
    scene.view_settings.exposure = ev
    if frame is not None:
        scene.view_settings.keyframe_insert("exposure", frame=frame)
    return ev


def set_world(scene, settings, sun, sky_image, disk_image=None):
    """The scene's world shows sky_image (and disk_image) and the lamp is set from sidecar fields sun."""
    mode = settings["sun_mode"]
    world = scene.world
    if world is None:
        world = scene.world = bpy.data.worlds.new("Firmament World")
    build_world_nodes(world, sky_image, disk_image, mapping_rotation_z(settings["north_offset"],
                                                                       sun["azimuth_at_center_deg"]), settings, sun)
    for obj in _our_lamps():
        _clear_animation(obj)  # a baked day's keyframes would override the new values
    if mode == "DISK":
        _remove_lamp()
    else:
        setup_lamp(scene, sun, settings["north_offset"], settings.get("sun_strength", 1.0))
    if mode == "DISK" and hasattr(world, "cycles"):  # resolve the small, bright disk when sampling the map
        world.cycles.sample_map_resolution = max(world.cycles.sample_map_resolution, sky_image.size[0] // 2)
    if hasattr(world, "sun_threshold"):  # EEVEE (4.2+): extract a sun from the map only when it has one
        world.sun_threshold = 10.0 if mode == "DISK" else 0.0
    return world


def apply(scene, settings, exr_path, sidecar_path, disk_path=None):
    """Sets up the world (and lamp) from a finished render.  Returns (sidecar dict, exposure applied
    or None).  The previous maps' images are removed from the file, never their files from disk."""
    sun = read_sidecar(sidecar_path)
    mode = settings["sun_mode"]
    if mode == "LAMP" and sun["contains_sun_disk"]:
        raise SetupError("the map holds the sun disk but sun mode 'Sun Lamp' adds a lamp: it would count twice")
    if mode == "DISK" and not sun["contains_sun_disk"]:
        raise SetupError("sun mode 'Disk in Map' needs a map with the disk")
    previous = our_images()
    sky_image = load_float_image(exr_path, "Firmament Sky")
    disk_image = None
    if mode == "LAMP_CAMERA_DISK":
        try:
            disk_image = load_float_image(disk_path, "Firmament Sky With Disk")
        except SetupError:
            bpy.data.images.remove(sky_image)
            raise
    set_world(scene, settings, sun, sky_image, disk_image)  # from here on the world changes
    _replace_images(previous, [(sky_image, "Firmament Sky")] + ([(disk_image, "Firmament Sky With Disk")] if disk_image else []))
    return sun, _set_exposure(scene, settings, sun)


def apply_series(scene, settings, frames):
    """Sets up a baked day from [(exr, sidecar)] of consecutive maps: the Environment Texture plays
    them as an image sequence from the scene's first frame, the lamp's rotation, strength, colour
    and visibility (and, when asked, the exposure) are keyframed per frame from each sidecar, and the
    scene's frame range becomes the series'.  Returns the sidecars."""
    suns = [read_sidecar(sc) for _exr, sc in frames]
    if any(s["contains_sun_disk"] for s in suns):
        raise SetupError("a baked day's maps must not hold the sun disk (the lamp is keyframed)")
    previous = our_images()
    sky_image = load_float_image(frames[0][0], "Firmament Sky")
    sky_image.source = "SEQUENCE"
    world = scene.world
    if world is None:
        world = scene.world = bpy.data.worlds.new("Firmament World")
    build_world_nodes(world, sky_image, None, mapping_rotation_z(settings["north_offset"], suns[0]["azimuth_at_center_deg"]),
                      dict(settings, ground="MAP", camera_disk=False))  # a static disk would not follow the lamp
    env = world.node_tree.nodes[NODE_PREFIX + "Sky"]
    first = scene.frame_start
    iu = env.image_user
    # frame f shows file number f - frame_start + 1 + offset: the series is numbered from 0
    iu.frame_start, iu.frame_offset, iu.frame_duration = first, -1, len(frames)
    iu.use_auto_refresh = True
    if hasattr(world, "sun_threshold"):
        world.sun_threshold = 0.0
    obj = _ensure_lamp(scene)
    _clear_animation(obj)
    edit = bpy.context.preferences.edit
    interpolation = edit.keyframe_new_interpolation_type
    edit.keyframe_new_interpolation_type = "CONSTANT"  # each frame holds its own sidecar's values
    try:
        for i, sun in enumerate(suns):
            f = first + i
            setup_lamp(scene, sun, settings["north_offset"], settings.get("sun_strength", 1.0))
            for prop in ("rotation_euler", "location", "hide_render", "hide_viewport"):
                obj.keyframe_insert(prop, frame=f)
            obj.data.keyframe_insert("energy", frame=f)
            obj.data.keyframe_insert("color", frame=f)
            _set_exposure(scene, settings, sun, frame=f)
    finally:
        edit.keyframe_new_interpolation_type = interpolation
    scene.frame_end = first + len(frames) - 1
    _replace_images(previous, [(sky_image, "Firmament Sky")])
    scene.frame_set(scene.frame_current)
    return suns


def eevee_engine():
    """EEVEE's engine id: BLENDER_EEVEE_NEXT in 4.2-4.5, BLENDER_EEVEE before and again from 5.0."""
    return "BLENDER_EEVEE_NEXT" if (4, 2, 0) <= bpy.app.version < (5, 0, 0) else "BLENDER_EEVEE"

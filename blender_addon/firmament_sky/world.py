"""World and sun setup from a rendered map and its sidecar.  Everything that can fail (reading
the sidecar, loading the images) happens before the world is touched, so a failure leaves the
previous world as it was.  What the add-on creates is tagged (images and the lamp carry the custom
property "firmament_sky", nodes are named "Firmament ...") so that re-generating replaces it."""

import json
import math
from array import array

import bpy
from mathutils import Color, Euler, Vector

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


class _Rebuild(Exception):
    """The world's firmament nodes are not those the settings and sun call for: build them anew."""


def _float32(x):
    return array("f", [x])[0]


def _same(current, value):
    """Whether a property already holds value (sockets hold float32: compared as such)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return isinstance(current, (int, float)) and _float32(current) == _float32(value)
    if isinstance(value, (tuple, list, Vector, Color, Euler)):
        current = tuple(current)
        return len(current) == len(value) and all(_same(c, v) for c, v in zip(current, value))
    return current is value or current == value


def set_changed(owner, attr, value):
    """Sets owner.attr only when it differs: even a set to the same value tags Blender's update."""
    if not _same(getattr(owner, attr), value):
        setattr(owner, attr, value)


class _Tree:
    """The world's firmament nodes as the builders below make them.  Building, each call creates its
    node, link or value; updating, the same calls find the nodes already there (a missing one, or
    one of another kind, raises _Rebuild), make no links, and set only the values that differ, so
    that the values come from one code whether the nodes are new or not."""

    def __init__(self, node_tree, build):
        self.nodes, self.links, self.build, self.seen = node_tree.nodes, node_tree.links, build, set()

    def node(self, kind, name, location, **attrs):
        """The node NODE_PREFIX + name, of bl_idname kind, with attrs: its structure (a value of the
        nodes the same call made goes through value/set)."""
        full = NODE_PREFIX + name
        n = self.nodes.get(full)
        if full in self.seen:
            return n  # made already by this build (a node two builders share)
        self.seen.add(full)
        if not self.build:
            if n is None or n.bl_idname != kind or any(getattr(n, k) != v for k, v in attrs.items()):
                raise _Rebuild
            return n
        n = self.nodes.new(kind)
        n.name = n.label = full
        n.location = location
        for k, v in attrs.items():
            setattr(n, k, v)
        return n

    def link(self, from_socket, to_socket):
        if self.build:
            self.links.new(from_socket, to_socket)

    def set(self, owner, attr, value):
        if self.build:
            setattr(owner, attr, value)
        else:
            set_changed(owner, attr, value)

    def value(self, socket, value):
        self.set(socket, "default_value", value)


def _env_node(tree, mapping, image, name, x, y, strength):
    env = tree.node("ShaderNodeTexEnvironment", name, (x, y), interpolation="Linear")
    if not tree.build and env.image_user.use_auto_refresh:
        raise _Rebuild  # a baked day's image sequence
    tree.set(env, "image", image)
    tree.link(mapping.outputs["Vector"], env.inputs["Vector"])
    bg = tree.node("ShaderNodeBackground", name + " Background", (x + 300, y))
    tree.value(bg.inputs["Strength"], strength)  # pixel values are radiance: 1:1 with the lamp (x Sky Strength)
    tree.link(env.outputs["Color"], bg.inputs["Color"])
    return bg


def _ours(nodes):
    return [n for n in nodes if n.name.startswith(NODE_PREFIX)]


def build_world_nodes(world, sky_image, disk_image, rotation_z, settings=None, sun=None, rebuild=False):
    """The world's firmament nodes for these maps, settings and sun: the nodes already there updated
    in place (only the values that changed) when they are those these call for, else built anew
    (or when rebuild).  Returns whether they were built anew."""
    if world.node_tree is None:  # before 5.0 a new world has no tree until use_nodes (deprecated in 5.0)
        world.use_nodes = True
    args = (sky_image, disk_image, rotation_z, settings or {}, sun)
    ours = _ours(world.node_tree.nodes)
    if ours and not rebuild:
        tree = _Tree(world.node_tree, build=False)
        try:
            _world_graph(tree, *args)
            if tree.seen == {n.name for n in ours}:
                return False
        except _Rebuild:
            pass
    nodes = world.node_tree.nodes
    for n in _ours(nodes):
        nodes.remove(n)
    _world_graph(_Tree(world.node_tree, build=True), *args)
    return True


def _world_graph(tree, sky_image, disk_image, rotation_z, settings, sun):
    out = _world_output(tree.nodes)
    if tree.build:
        out.location = (900, 300)
    coords = tree.node("ShaderNodeTexCoord", "Coordinates", (-500, 300))
    mapping = tree.node("ShaderNodeMapping", "North", (-300, 300), vector_type="POINT")
    tree.value(mapping.inputs["Rotation"], (0.0, 0.0, rotation_z))
    tree.link(coords.outputs["Generated"], mapping.inputs["Vector"])
    sky_bg = _env_node(tree, mapping, sky_image, "Sky", 0, 300, settings.get("sky_strength", 1.0))
    if settings.get("ground", "MAP") != "MAP":
        _ground_nodes(tree, mapping, sky_bg, settings, sun)
    if settings.get("sun_mode") == "LAMP" and settings.get("camera_disk") and sun and \
            sun["elevation_deg"] + sun["angular_diameter_deg"] / 2 >= 0.0:
        _camera_rolloff_nodes(tree, sky_bg, settings, sun)  # before the disk: the disk stays whole
        _camera_disk_nodes(tree, mapping, sky_bg, settings, sun)
    if disk_image is None:
        tree.link(sky_bg.outputs["Background"], out.inputs["Surface"])
        return
    # camera rays see the map with the disk; every other ray the one without (the lamp lights)
    disk_bg = _env_node(tree, mapping, disk_image, "Sky With Disk", 0, 0, settings.get("sky_strength", 1.0))
    path = tree.node("ShaderNodeLightPath", "Light Path", (300, 600))
    mix = tree.node("ShaderNodeMixShader", "Camera Sees Disk", (650, 300))
    tree.link(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    tree.link(sky_bg.outputs["Background"], mix.inputs[1])
    tree.link(disk_bg.outputs["Background"], mix.inputs[2])
    tree.link(mix.outputs["Shader"], out.inputs["Surface"])


def _clear_animation(obj):
    for idb in (obj, obj.data):
        if idb.animation_data is not None:
            idb.animation_data_clear()


def _mix_into(tree, bg, name, factor, rgb, location):
    """Between the Background's colour and what feeds it: where factor is 1, the colour rgb."""
    source = bg.inputs["Color"].links[0].from_socket if tree.build else None
    mix = tree.node("ShaderNodeMix", name, location, data_type="RGBA")
    fac = [i for i in mix.inputs if i.name == "Factor" and i.type == "VALUE"][0]
    a, b = [i for i in mix.inputs if i.type == "RGBA"][:2]
    tree.link(factor, fac)
    tree.link(source, a)
    tree.value(b, (rgb[0], rgb[1], rgb[2], 1.0))
    tree.link([o for o in mix.outputs if o.type == "RGBA"][0], bg.inputs["Color"])


def _ground_nodes(tree, mapping, bg, settings, sun):
    """Below the horizon (the looked-up direction's z < 0) the world shows a chosen ground instead of
    the map's: black, or a Lambertian ground of the given reflectance under this sky (radiance
    reflectance x global horizontal illuminance / (683 pi), in Blender's units)."""
    sep = tree.node("ShaderNodeSeparateXYZ", "Direction", (-100, 600))
    tree.link(mapping.outputs["Vector"], sep.inputs["Vector"])
    below = tree.node("ShaderNodeMath", "Below Horizon", (100, 600), operation="LESS_THAN")
    tree.value(below.inputs[1], 0.0)
    tree.link(sep.outputs["Z"], below.inputs[0])
    lum = (sun or {}).get("global_lux") or 0.0
    k = lum / (683.0 * math.pi) if settings["ground"] == "COLOUR" else 0.0
    rgb = Color(settings.get("ground_colour", (0.0, 0.0, 0.0)))
    _mix_into(tree, bg, "Ground", below.outputs["Value"], [c * k for c in rgb], (250, 450))


# The camera's highlight roll-off, in scene-linear values after the suggested exposure: Filmic and AgX
# (the default view transforms) reach white at 0.18 x 2^6.5 = 16.3, so an aureole above that clips
# to the disk's white.  Above the knee, a luminance x stops over it shows as S (1 - e^(-x/S)) stops
# (slope 1 at the knee, never more than S stops over it): at most 2.5 x 2^1.2 = 5.7, which Filmic
# shows at 0.93 and AgX at 0.87 of white, below the disk (about 3e4: white in any transform).
ROLLOFF_KNEE = 2.5
ROLLOFF_STOPS = 1.2


def _math(tree, name, location, operation, a, b=None, c=None):
    """A Math node; its inputs are sockets (linked) or numbers."""
    m = tree.node("ShaderNodeMath", name, location, operation=operation)
    for i, v in enumerate((a, b, c)):
        if v is None:
            continue
        if isinstance(v, (int, float)):
            tree.value(m.inputs[i], v)
        else:
            tree.link(v, m.inputs[i])
    return m.outputs["Value"]


def _camera_rolloff_nodes(tree, bg, settings, sun):
    """For camera rays only, the world's highlights above the knee rolled off (hue kept: the colour
    scaled by the luminance's ratio), so that at the suggested exposure the aureole stays below white
    and the camera's sun disk stands out of it.  Every other ray (lighting, reflections) sees the map
    as it is.  Nothing is added without an exposure to key it to (night)."""
    ev = metered_exposure(sun, settings.get("metering", "HORIZONTAL"))
    if ev is None:
        return
    knee = ROLLOFF_KNEE * 2.0 ** -ev / max(settings.get("sky_strength", 1.0), 1e-6)  # in the map's values
    source = bg.inputs["Color"].links[0].from_socket if tree.build else None
    lum = tree.node("ShaderNodeRGBToBW", "Luminance", (-100, 1200))
    tree.link(source, lum.inputs["Color"])
    above = _math(tree, "Over Knee", (50, 1200), "MAXIMUM", lum.outputs["Val"], knee)
    x = _math(tree, "Stops Over Knee", (200, 1200), "LOGARITHM", _math(
        tree, "Ratio to Knee", (100, 1350), "DIVIDE", above, knee), 2.0)
    fall = _math(tree, "Shoulder", (350, 1200), "EXPONENT",
                 _math(tree, "Shoulder Rate", (250, 1350), "MULTIPLY", x, -1.0 / ROLLOFF_STOPS))
    shown = _math(tree, "Stops Shown", (500, 1200), "MULTIPLY_ADD", fall, -ROLLOFF_STOPS, ROLLOFF_STOPS)
    scale = _math(tree, "Roll-off", (650, 1200), "POWER", 2.0,
                  _math(tree, "Stops Removed", (550, 1350), "SUBTRACT", shown, x))
    path = tree.node("ShaderNodeLightPath", "Camera Path", (100, 1000))  # the disk's nodes use it too
    mix = tree.node("ShaderNodeMix", "Camera Roll-off", (800, 1200), data_type="RGBA", blend_type="MULTIPLY")
    fac = [i for i in mix.inputs if i.name == "Factor" and i.type == "VALUE"][0]
    a, b = [i for i in mix.inputs if i.type == "RGBA"][:2]
    tree.link(path.outputs["Is Camera Ray"], fac)
    tree.link(source, a)
    tree.link(scale, b)
    tree.link([o for o in mix.outputs if o.type == "RGBA"][0], bg.inputs["Color"])


def _camera_disk_nodes(tree, mapping, bg, settings, sun):
    """The sun disk for camera rays only (the lamp lights; nothing is counted twice): a uniform
    disk of the sun's angular size and its radiance, the direct normal irradiance / the disk's solid
    angle, where the looked-up direction is within the sun's radius."""
    radius = math.radians(sun["angular_diameter_deg"]) / 2
    solid_angle = 2 * math.pi * (1 - math.cos(radius))
    dot = tree.node("ShaderNodeVectorMath", "Toward Sun", (-100, 800), operation="DOT_PRODUCT")
    tree.link(mapping.outputs["Vector"], dot.inputs[0])
    tree.value(dot.inputs[1], sun["direction"])  # the map's frame: the mapping's output
    inside = tree.node("ShaderNodeMath", "In Sun Disk", (100, 800), operation="GREATER_THAN")
    tree.value(inside.inputs[1], math.cos(radius))
    tree.link(dot.outputs["Value"], inside.inputs[0])
    path = tree.node("ShaderNodeLightPath", "Camera Path", (100, 1000))
    camera = tree.node("ShaderNodeMath", "Camera Sees Sun", (250, 900), operation="MULTIPLY")
    tree.link(inside.outputs["Value"], camera.inputs[0])
    tree.link(path.outputs["Is Camera Ray"], camera.inputs[1])
    scale = settings.get("sun_strength", 1.0) / max(settings.get("sky_strength", 1.0), 1e-6) / solid_angle
    rgb = Color(sun["irradiance_rgb"]).from_rec709_linear_to_scene_linear()
    _mix_into(tree, bg, "Sun Disk", camera.outputs["Value"], [c * scale for c in rgb], (450, 600))


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
    set_changed(light, "energy", max(peak, 0.0) * sun.get("strength", 1.0))
    set_changed(light, "color", [c / peak for c in rgb] if peak > 0.0 else (1.0, 1.0, 1.0))
    set_changed(light, "angle", math.radians(sun["angular_diameter_deg"]))
    if obj.get(CLOUD_KEY) != sun.get("cloud_transmittance", 1.0):
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
    set_changed(obj, "rotation_mode", "XYZ")
    set_changed(obj, "rotation_euler", d.to_track_quat("Z", "Y").to_euler())  # the lamp shines along its -Z
    centre, radius = _scene_bounds(scene)
    set_changed(obj, "location", centre + d * (radius + 2.0))  # only for the viewport: outside the scene, toward the sun
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
        set_changed(world.cycles, "sample_map_resolution", max(world.cycles.sample_map_resolution, sky_image.size[0] // 2))
    if hasattr(world, "sun_threshold"):  # EEVEE (4.2+): extract a sun from the map only when it has one
        set_changed(world, "sun_threshold", 10.0 if mode == "DISK" else 0.0)
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
                      dict(settings, ground="MAP", camera_disk=False), rebuild=True)  # a static disk would not follow the lamp
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

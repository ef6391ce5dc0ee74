"""Shared by the Blender tests: arguments, installing and enabling the built zip, checks that count
and fail loudly.  Imported from the test scripts (their folder is put on sys.path)."""

import os
import sys

import bpy  # first: with the bpy module, Blender's own modules come with it
import addon_utils  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
argv = sys.argv[sys.argv.index("--") + 1:]
ZIP, EXE, OUT = argv[0], argv[1], argv[2]

_checks = {"passed": 0, "failed": [], "deprecated": []}


def check(cond, what):
    if cond:
        _checks["passed"] += 1
        print("ok    %s" % what)
    else:
        _checks["failed"].append(what)
        print("FAIL  %s" % what)


def close(a, b, tol, what):
    check(abs(a - b) <= tol, "%s: %.6g vs %.6g (tolerance %g)" % (what, a, b, tol))


def finish():
    check(not _checks["deprecated"], "the add-on uses no deprecated API: %s" % ("; ".join(_checks["deprecated"]) or "none"))
    print("%d checks passed, %d failed" % (_checks["passed"], len(_checks["failed"])))
    if _checks["failed"]:
        raise SystemExit("failed: " + "; ".join(_checks["failed"]))


LEGACY = bpy.app.version < (4, 2, 0)  # 3.4-4.1: a legacy add-on; 4.2+: an extension
MODULE = "firmament_sky" if LEGACY else "bl_ext.user_default.firmament_sky"


def re_escape(text):
    import re
    return re.escape(text)


def addon_dir():
    return os.path.dirname(sys.modules[MODULE].__file__)


def install_and_enable():
    """Installs the zip through this Blender's own install path and enables it, with no preference
    set (the add-on must find its bundled executable).  Returns the add-on's module."""
    print("Blender %s (%s)" % (bpy.app.version_string, "legacy add-on" if LEGACY else "extension"))
    if LEGACY:
        bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
        if addon_utils.enable(MODULE, default_set=True, handle_error=None) is None:
            raise SystemExit("the add-on did not enable")
    else:
        res = bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
        check(res == {"FINISHED"}, "extension installed from the zip: %s" % res)
    check(MODULE in bpy.context.preferences.addons, "enabled as %s" % MODULE)
    # a deprecated API used by the add-on (e.g. World.use_nodes in 5.0) fails the test at finish()
    import warnings
    warnings.filterwarnings("always", category=DeprecationWarning, module=re_escape(MODULE) + r"(\..*)?$")
    shown = warnings.showwarning

    def record(message, category, filename, lineno, *args, **kwargs):
        if category is DeprecationWarning and os.path.realpath(filename).startswith(os.path.realpath(addon_dir())):
            _checks["deprecated"].append("%s:%d: %s" % (os.path.basename(filename), lineno, message))
        return shown(message, category, filename, lineno, *args, **kwargs)
    warnings.showwarning = record
    mod = sys.modules[MODULE]
    where = os.path.join(bpy.utils.user_resource("SCRIPTS"), "addons") if LEGACY else \
        os.path.join(bpy.utils.user_resource("EXTENSIONS"), "user_default")
    check(os.path.dirname(addon_dir()) == os.path.realpath(where) or os.path.dirname(addon_dir()) == where,
          "installed into %s" % where)
    prefs = bpy.context.preferences.addons[MODULE].preferences
    check(prefs.executable == "", "no executable set in the preferences")
    return mod


def submodule(name):
    """One of the installed add-on's modules (operators, world, ...)."""
    import importlib
    return importlib.import_module(MODULE + "." + name)


def preferences():
    return bpy.context.preferences.addons[MODULE].preferences


def shipped_preset(name):
    path = os.path.join(addon_dir(), "presets", "skies", name + ".json")
    if not os.path.isfile(path):
        raise SystemExit("shipped preset missing from the installed add-on: " + path)
    return path


def fast_settings(scene, width=128):
    p = scene.firmament_sky
    p.resolution = width
    p.quality = "preview"
    p.threads = 2
    return p


def world_images():
    return [img for img in bpy.data.images if img.get("firmament_sky")]


def sun_lamps():
    return [o for o in bpy.data.objects if o.type == "LIGHT" and o.data.type == "SUN"]


def image_pixels(img):
    """RGBA float pixels, rows bottom-up (row 0 = nadir), as an array('f')."""
    from array import array
    buf = array("f", [0.0]) * (img.size[0] * img.size[1] * 4)
    img.pixels.foreach_get(buf)
    return buf


def sidecar_of(img):
    import json
    with open(os.path.splitext(bpy.path.abspath(img.filepath))[0] + ".json") as f:
        return json.load(f)


def sky_image():
    """The map the world's lighting uses (not the camera-only one with the disk)."""
    imgs = [i for i in world_images() if "Disk" not in i.name]
    if len(imgs) != 1:
        raise SystemExit("expected one sky image, found %s" % [i.name for i in imgs])
    return imgs[0]


# luminance (CIE Y) of linear RGB in each working space Blender 5.0 offers: the Y row of its RGB->XYZ
LUMINANCE = {"Linear Rec.709": (0.2126729, 0.7151522, 0.0721750), "Linear": (0.2126729, 0.7151522, 0.0721750),
             "Linear Rec.2020": (0.2627002, 0.6779981, 0.0593017), "ACEScg": (0.2722287, 0.6740818, 0.0536895)}


def working_space():
    cs = getattr(bpy.data, "colorspace", None)
    return cs.working_space if cs is not None else "Linear Rec.709"


def luminance(rgb, space=None):
    k = LUMINANCE[space or working_space()]
    return k[0] * rgb[0] + k[1] * rgb[1] + k[2] * rgb[2]


def material(name, rgb):
    """A plain Lambertian (Diffuse BSDF) material: a white one reflects E/pi exactly."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        if n.type != "OUTPUT_MATERIAL":
            nodes.remove(n)
    out = [n for n in nodes if n.type == "OUTPUT_MATERIAL"][0]
    d = nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*rgb, 1.0)
    mat.node_tree.links.new(d.outputs["BSDF"], out.inputs["Surface"])
    return mat


def _quad(name, x0, x1, y0, y1, z, mat, scene):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)], [], [(0, 1, 2, 3)])
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    obj.data.materials.append(mat)
    scene.collection.objects.link(obj)
    return obj


def card_scene(scene, ground_half=40.0, ortho_scale=10.0):
    """A grey ground (albedo 0.5), a 4 m pillar whose shadow falls on it, and a white horizontal card
    (albedo 1) 0.5 m up, far enough from the pillar to see the whole sky; an orthographic camera looks
    straight down.  Returns the camera."""
    for o in list(bpy.data.objects):
        if o.type != "LIGHT" or not o.get("firmament_sky"):
            bpy.data.objects.remove(o)
    _quad("Ground", -ground_half, ground_half, -ground_half, ground_half, 0.0, material("Ground", (0.5, 0.5, 0.5)), scene)
    _quad("Card", 0.5, 3.5, 0.5, 3.5, 0.5, material("White", (1.0, 1.0, 1.0)), scene)
    mesh = bpy.data.meshes.new("Pillar")
    import bmesh
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0)
    bm.to_mesh(mesh)
    bm.free()
    pillar = bpy.data.objects.new("Pillar", mesh)
    pillar.scale = (1.5, 1.5, 4.0)
    pillar.location = (-2.5, -2.5, 2.0)
    pillar.data.materials.append(material("Pillar", (0.5, 0.5, 0.5)))
    scene.collection.objects.link(pillar)
    cam = bpy.data.objects.new("Top camera", bpy.data.cameras.new("Top camera"))
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = ortho_scale
    cam.location = (0.0, 0.0, 20.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def render_settings(scene, res=(48, 48), samples=16, engine="CYCLES"):
    r = scene.render
    r.engine = engine
    r.resolution_x, r.resolution_y, r.resolution_percentage = res[0], res[1], 100
    if engine == "CYCLES":
        scene.cycles.device = "CPU"
        scene.cycles.samples = samples
        scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
        scene.cycles.max_bounces = 2
        if scene.world is not None:
            scene.world.cycles.sample_map_resolution = 256
    scene.view_settings.view_transform = "Standard"


def render_linear(scene, path):
    """Renders the scene's camera to a float EXR and returns (pixels, width, height), the values as
    rendered (scene linear, no view transform)."""
    r = scene.render
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.filepath = path
    bpy.ops.render.render(write_still=True)
    return load_linear(path)


def load_linear(path):
    img = bpy.data.images.load(path, check_existing=False)
    img.colorspace_settings.name = "Non-Color"  # the file's numbers, no conversion
    return image_pixels(img), img.size[0], img.size[1]


def classify(scene, cam, w, hgt):
    """For an orthographic top camera: 'card', 'lit' (ground in sun), 'shade' (ground in the pillar's
    shadow), 'sky' (the world seen looking down: the map's nadir) -> pixel indices (into RGBA pixels), found by casting rays into the scene; only pixels
    whose 8 neighbours are of the same kind (the pixel filter blends edges)."""
    from mathutils import Vector
    dg = bpy.context.evaluated_depsgraph_get()
    lamp = sun_lamps()[0]
    to_sun = (lamp.matrix_world.to_3x3() @ Vector((0, 0, 1))).normalized()
    half = cam.data.ortho_scale / 2
    kind = {}
    for y in range(hgt):
        for x in range(w):
            o = Vector((cam.location.x - half + (x + 0.5) / w * 2 * half,
                        cam.location.y - half * hgt / w + (y + 0.5) / hgt * 2 * half * hgt / w, cam.location.z))
            hit, loc, normal, _i, obj, _m = scene.ray_cast(dg, o, Vector((0, 0, -1)))
            if hit and obj.name == "Card":
                kind[x, y] = "card"
            elif hit and obj.name == "Ground":
                kind[x, y] = "shade" if scene.ray_cast(dg, loc + normal * 1e-3, to_sun)[0] else "lit"
            elif not hit:
                kind[x, y] = "sky"
    out = {"card": [], "lit": [], "shade": [], "sky": []}
    for (x, y), k in kind.items():
        if all(kind.get((x + i, y + j), "sky" if k == "sky" else None) == k for i in (-1, 0, 1) for j in (-1, 0, 1)):
            out[k].append(4 * (y * w + x))
    return out


def mean_luminance(px, idx):
    return sum(luminance(px[k:k + 3]) for k in idx) / max(1, len(idx))


RENDER_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "render_file.py")


def render_in_new_process(blend, out=None):
    """Renders a saved .blend in a fresh Blender process, where the add-on is not enabled: the
    still to OUT (an EXR), or without OUT the animation to the file's own output path (3.4: the
    command line `blender -b FILE.blend -a`).  render_file.py first checks that every map of the
    file is referenced relative to it and exists."""
    import subprocess
    mode = "still" if out else "animation"
    if LEGACY:
        cmds = [[bpy.app.binary_path, "-b", blend, "--python-exit-code", "1", "-P", RENDER_FILE, "--", blend,
                 mode if out else "check", out or ""]]
        if not out:
            cmds.append([bpy.app.binary_path, "-b", blend, "-a"])
    else:
        cmds = [[sys.executable, RENDER_FILE, "--", blend, mode, out or ""]]
    for cmd in cmds:
        print("$ " + " ".join(cmd))
        r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        lines = [ln for ln in r.stdout.splitlines() if not ln.startswith("Fra:")]
        check(r.returncode == 0, "%s in a new process (exit %d)%s" % (
            mode, r.returncode, "" if r.returncode == 0 else ":\n" + "\n".join(lines[-15:])))


def env_of(bg):
    """The Environment Texture feeding a Background, through the add-on's Mix nodes (ground, camera
    disk: their first colour input carries the map)."""
    node = bg.inputs["Color"].links[0].from_node
    while node.type == "MIX":
        node = [i for i in node.inputs if i.type == "RGBA"][0].links[0].from_node
    return node

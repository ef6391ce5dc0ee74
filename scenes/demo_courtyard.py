"""A small architectural demo scene: a U-shaped three-wing building around a courtyard open to the
north, with window bands, on a ground plane, and a camera looking south into the courtyard (the
south wing's shadow falls into it for a sun in the southern sky).  Axes as in the add-on: +Y north,
+X east, +Z up, metres.

Use:  blender -b --factory-startup -P scenes/demo_courtyard.py -- [--save FILE.blend]
or, from Python:  import demo_courtyard; demo_courtyard.build(bpy.context.scene)
"""

import math
import sys

import bpy

# (name, x range, y range, height): the wings; the courtyard is x in [-5, 5], y in [-5, 6]
WINGS = (
    ("South wing", (-8.0, 8.0), (-8.0, -5.0), 7.0),
    ("East wing", (5.0, 8.0), (-5.0, 6.0), 5.0),
    ("West wing", (-8.0, -5.0), (-5.0, 6.0), 5.0),
)
GROUND_SIZE = 60.0
CAMERA_LOCATION = (-4.0, 20.0, 7.0)
CAMERA_TARGET = (0.5, -2.0, 1.5)


def _material(name, colour, roughness, metallic=0.0, transmission=0.0):
    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    spec = bsdf.inputs.get("Specular") or bsdf.inputs.get("Specular IOR Level")
    if spec is not None:
        spec.default_value = 0.5 if transmission == 0.0 and metallic == 0.0 else spec.default_value
    mat.diffuse_color = (*colour, 1.0)
    return mat


def _box(name, x, y, z, material, collection):
    """An axis-aligned box from ranges (x0, x1), (y0, y1), (z0, z1)."""
    mesh = bpy.data.meshes.new(name)
    (x0, x1), (y0, y1), (z0, z1) = x, y, z
    verts = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
             (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    obj.data.materials.append(material)
    collection.objects.link(obj)
    return obj


def _windows(wing, x, y, height, glass, collection):
    """Window bands: dark glazing panels 2 cm proud of the courtyard-facing facade, one per storey."""
    storeys = int(height // 3.0)
    for s in range(storeys):
        z = (s * 3.0 + 0.9, s * 3.0 + 2.4)
        if wing == "South wing":  # facade facing north, at y = -5
            for i in range(-4, 4):
                _box("%s window %d.%d" % (wing, s, i), (i + 0.2, i + 0.8), (y[1], y[1] + 0.02), z, glass, collection)
        else:  # east wing faces west (x = 5), west wing faces east (x = -5)
            face = x[0] if wing == "East wing" else x[1]
            sign = -1.0 if wing == "East wing" else 1.0
            for i in range(-4, 6):
                xs = sorted((face, face + sign * 0.02))
                _box("%s window %d.%d" % (wing, s, i), tuple(xs), (i + 0.2, i + 0.8), z, glass, collection)


def build(scene):
    """Builds the demo into scene (its objects go to a 'Demo courtyard' collection; the default
    cube, light and camera of a factory scene are removed).  Returns the camera object."""
    for name in ("Cube", "Light", "Camera"):
        obj = bpy.data.objects.get(name)
        if obj is not None:
            bpy.data.objects.remove(obj)
    coll = bpy.data.collections.get("Demo courtyard") or bpy.data.collections.new("Demo courtyard")
    if coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    plaster = _material("Plaster", (0.70, 0.66, 0.60), 0.8)
    ground = _material("Paving", (0.35, 0.35, 0.35), 0.9)
    glass = _material("Glazing", (0.02, 0.025, 0.03), 0.05)
    g = GROUND_SIZE / 2
    _box("Ground", (-g, g), (-g, g), (-0.1, 0.0), ground, coll)
    for name, x, y, height in WINGS:
        _box(name, x, y, (0.0, height), plaster, coll)
        _windows(name, x, y, height, glass, coll)
    cam_data = bpy.data.cameras.new("Demo camera")
    cam_data.lens = 24.0
    cam = bpy.data.objects.new("Demo camera", cam_data)
    coll.objects.link(cam)
    cam.location = CAMERA_LOCATION
    direction = [t - c for t, c in zip(CAMERA_TARGET, CAMERA_LOCATION)]
    from mathutils import Vector
    cam.rotation_euler = Vector(direction).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    scene.render.engine = "CYCLES"
    scene.view_settings.view_transform = "Filmic" if "Filmic" in [
        v.identifier for v in type(scene.view_settings).bl_rna.properties["view_transform"].enum_items] else \
        scene.view_settings.view_transform
    return cam


if __name__ == "__main__":
    build(bpy.context.scene)
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if "--save" in argv:
        bpy.ops.wm.save_as_mainfile(filepath=argv[argv.index("--save") + 1])

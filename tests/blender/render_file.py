"""Run in a fresh Blender process by the tests (harness.render_in_new_process): opens a saved .blend
(the bpy module; Blender 3.4 opens it from its command line), checks that every map of the add-on is
referenced relative to the .blend and exists, then renders the still to OUT or the animation.
Usage: render_file.py -- FILE.blend still|animation|check [OUT.exr]"""

import os
import sys

import bpy

blend, mode, out = (sys.argv[sys.argv.index("--") + 1:] + [""])[:3]
if os.path.abspath(bpy.data.filepath or "") != os.path.abspath(blend):
    bpy.ops.wm.open_mainfile(filepath=blend)
bad = []
for img in bpy.data.images:
    if not img.get("firmament_sky") or img.packed_file is not None:  # packed: no file needed
        continue
    path = bpy.path.abspath(img.filepath)
    if not img.filepath.startswith("//"):
        bad.append("%s: absolute path %s" % (img.name, img.filepath))
    elif not os.path.isfile(path):
        bad.append("%s: missing %s" % (img.name, path))
if bad:
    raise SystemExit("maps: " + "; ".join(bad))
print("maps: %d, all packed or relative and present" % len([i for i in bpy.data.images if i.get("firmament_sky")]))
if mode == "still":
    r = bpy.context.scene.render
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.filepath = out
    bpy.ops.render.render(write_still=True)
elif mode == "animation":
    bpy.ops.render.render(animation=True)

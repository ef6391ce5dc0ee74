"""Where the maps go and that saved files keep their sky: an unsaved file's map goes to the add-on's
cache; saving copies it beside the .blend (//firmament/) with a relative path; Generate in a saved
file writes there and deletes no map (file A keeps its sky after Save As B and a Generate in B);
Clean Unused Maps removes only maps this file does not use; a saved, moved (deeper folder) .blend
reopened in a new process renders the same pixels."""

import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402

h.install_and_enable()
maps = h.submodule("maps")
scene = bpy.context.scene
bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("golden-hour"))
h.fast_settings(scene, width=64)
cam = h.card_scene(scene)
h.render_settings(scene, res=(24, 24), samples=8)

def map_path():
    return bpy.path.abspath(h.sky_image().filepath)

h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate in an unsaved file")
# the lamp stands outside the scene (ground 80 m wide) toward the sun, out of the way
lamp = h.sun_lamps()[0]
h.check(lamp.location.length > 40.0 and lamp.location.z > 0.0, "the lamp is placed outside the scene: %s" % (tuple(round(c, 1) for c in lamp.location),))
m0 = map_path()
h.check(os.path.dirname(os.path.dirname(m0)) == maps.cache_dir(), "unsaved: the map is in the cache (%s)" % m0)

dir_a, dir_b = os.path.join(h.OUT, "A"), os.path.join(h.OUT, "B")
os.makedirs(dir_a)
os.makedirs(dir_b)
blend_a = os.path.join(dir_a, "a.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend_a)
rel = h.sky_image().filepath
h.check(rel.startswith("//firmament/"), "saved: the map is referenced relative to the .blend (%s)" % rel)
h.check(os.path.isfile(os.path.join(dir_a, rel[2:])), "saved: the map was copied beside the .blend")
m_a = map_path()

# Save As B (another folder), Generate in B: A's map stays on disk
blend_b = os.path.join(dir_b, "b.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend_b)
h.check(h.sky_image().filepath.startswith("//firmament/") and map_path().startswith(dir_b + os.sep),
        "Save As elsewhere: the map is copied beside the new .blend (%s)" % h.sky_image().filepath)
m_b1 = map_path()
h.check(bpy.ops.firmament_sky.generate() == {"FINISHED"}, "generate in the saved file B")
m_b2 = map_path()
h.check(m_b2.startswith(os.path.join(dir_b, "firmament") + os.sep) and h.sky_image().filepath.startswith("//firmament/"),
        "a saved file's new map goes to //firmament/ (%s)" % h.sky_image().filepath)
for path, what in ((m0, "the unsaved file's map"), (m_a, "A's map"), (m_b1, "B's previous map")):
    h.check(os.path.isfile(path), "Generate deleted no map: %s is still there" % what)

# Clean Unused Maps: B's previous map and the cache's go; the map in use and A's stay
bpy.ops.wm.save_mainfile()
h.check(bpy.ops.firmament_sky.clean_maps() == {"FINISHED"}, "clean unused maps")
h.check(not os.path.exists(m_b1) and not os.path.exists(m0), "clean removed the maps B does not use")
h.check(os.path.isfile(m_b2) and os.path.isfile(m_a), "clean kept B's map in use and A's map")

# moved project: render here, move the folder one level deeper, render in a new process
before, w, hgt = h.render_linear(scene, os.path.join(h.OUT, "before.exr"))
bpy.ops.wm.save_mainfile()
moved = os.path.join(h.OUT, "elsewhere", "deeper", "B")
os.makedirs(os.path.dirname(moved))
shutil.move(dir_b, moved)
after_path = os.path.join(h.OUT, "after.exr")
h.render_in_new_process(os.path.join(moved, "b.blend"), after_path)
after, w2, h2 = h.load_linear(after_path)
mean_b = sum(before[k] for k in range(0, len(before), 4)) / (w * hgt)
diff = sum(abs(before[k] - after[k]) for k in range(0, len(before), 4)) / (w * hgt)
h.check((w, hgt) == (w2, h2) and diff < 0.02 * mean_b,
        "the moved .blend renders the same pixels: mean |difference| %.3g of mean %.3g" % (diff, mean_b))

# Pack Maps: the packed file renders the same without its map folder
bpy.ops.wm.open_mainfile(filepath=os.path.join(moved, "b.blend"))
h.check(bpy.ops.firmament_sky.pack_maps() == {"FINISHED"}, "Pack Maps")
imgs = [i for i in bpy.data.images if i.get("firmament_sky")]
h.check(imgs and all(i.packed_file is not None for i in imgs), "every map packed (%d)" % len(imgs))
bpy.ops.wm.save_mainfile()
shutil.rmtree(os.path.join(moved, "firmament"))
packed_path = os.path.join(h.OUT, "packed.exr")
h.render_in_new_process(os.path.join(moved, "b.blend"), packed_path)
packed, w3, h3 = h.load_linear(packed_path)
diff = sum(abs(before[k] - packed[k]) for k in range(0, len(before), 4)) / (w * hgt)
h.check((w, hgt) == (w3, h3) and diff < 0.02 * mean_b,
        "the packed .blend renders the same pixels without its maps: mean |difference| %.3g of mean %.3g" % (diff, mean_b))
h.finish()

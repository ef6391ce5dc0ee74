"""Shared by the Blender tests: arguments, installing and enabling the built zip, checks that count
and fail loudly.  Imported from the test scripts (their folder is put on sys.path)."""

import os
import sys

import addon_utils
import bpy

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
argv = sys.argv[sys.argv.index("--") + 1:]
ZIP, EXE, OUT = argv[0], argv[1], argv[2]

_checks = {"passed": 0, "failed": []}


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
    print("%d checks passed, %d failed" % (_checks["passed"], len(_checks["failed"])))
    if _checks["failed"]:
        raise SystemExit("failed: " + "; ".join(_checks["failed"]))


def install_and_enable():
    """Installs the zip into the isolated user scripts folder and enables it (as a user would)."""
    bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    mod = addon_utils.enable("firmament_sky", default_set=True, handle_error=None)
    if mod is None:
        raise SystemExit("the add-on did not enable")
    installed = os.path.join(bpy.utils.user_resource("SCRIPTS"), "addons", "firmament_sky")
    check(os.path.isdir(installed), "zip installed into the user scripts folder")
    prefs = bpy.context.preferences.addons["firmament_sky"].preferences
    prefs.executable = EXE
    return mod


def shipped_preset(name):
    path = os.path.join(bpy.utils.user_resource("SCRIPTS"), "addons", "firmament_sky", "presets", "skies",
                        name + ".json")
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

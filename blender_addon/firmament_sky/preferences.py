"""Add-on preferences: where the firmament executable is."""

import os
import shutil

import bpy
from bpy.props import StringProperty

ADDON_DIR = os.path.dirname(os.path.abspath(__file__))


class FirmamentSkyPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    executable: StringProperty(
        name="firmament Executable", subtype="FILE_PATH", default="",
        description="Path to the firmament executable; empty: $FIRMAMENT_EXECUTABLE, then firmament on PATH, "
                    "then a copy next to the add-on")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "executable")
        found, where = find_executable(self.executable)
        if found:
            layout.label(text="Using: %s (%s)" % (found, where), icon="CHECKMARK")
        else:
            layout.label(text="firmament was not found: set the path above", icon="ERROR")


def preferences(context=None):
    """The add-on's preferences, or None (e.g. classes registered without an enabled add-on)."""
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def _is_executable(path):
    return bool(path) and os.path.isfile(path) and os.access(path, os.X_OK)


def find_executable(configured=""):
    """(path, where it came from) or (None, why not)."""
    if configured:
        path = bpy.path.abspath(configured)
        if _is_executable(path):
            return path, "preferences"
        return None, "the preferences' path %s is not an executable file" % path
    env = os.environ.get("FIRMAMENT_EXECUTABLE")
    if env:
        if _is_executable(env):
            return env, "$FIRMAMENT_EXECUTABLE"
        return None, "$FIRMAMENT_EXECUTABLE=%s is not an executable file" % env
    on_path = shutil.which("firmament")
    if on_path:
        return on_path, "PATH"
    for candidate in (os.path.join(ADDON_DIR, "bin", "firmament"), os.path.join(ADDON_DIR, "firmament")):
        if _is_executable(candidate):
            return candidate, "add-on folder"
    return None, "not in the preferences, $FIRMAMENT_EXECUTABLE, PATH or the add-on folder"

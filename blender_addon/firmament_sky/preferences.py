"""Add-on preferences: where the firmament executable is."""

import os
import shutil

import bpy
from bpy.props import StringProperty

from .runner import executable_name

ADDON_DIR = os.path.dirname(os.path.abspath(__file__))


class FirmamentSkyPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    executable: StringProperty(
        name="firmament Executable", subtype="FILE_PATH", default="",
        description="Path to a firmament executable to use instead of the one bundled with the add-on "
                    "(empty: $FIRMAMENT_EXECUTABLE, then the bundled one, then firmament on PATH)")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "executable")
        found, where = find_executable(self.executable)
        if found:
            layout.label(text="Using: %s (%s)" % (found, where), icon="CHECKMARK")
        else:
            layout.label(text="firmament was not found: set the path above", icon="ERROR")


class NotFound(RuntimeError):
    pass


def executable_and_options(context=None):
    """(executable, its options table) for the add-on's settings; NotFound or OptionsError say why not."""
    from . import options
    prefs = preferences(context)
    exe, why = find_executable(prefs.executable if prefs else "")
    if exe is None:
        raise NotFound("the firmament executable was not found (%s); set its path in Preferences > Add-ons > "
                       "Firmament Sky" % why)
    return exe, options.load(exe)


def preferences(context=None):
    """The add-on's preferences, or None (e.g. classes registered without an enabled add-on)."""
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


BUNDLED = os.path.join(ADDON_DIR, "bin", executable_name())  # scripts/build-addon puts it there


def _is_executable(path):
    return bool(path) and os.path.isfile(path) and os.access(path, os.X_OK)


def bundled_executable():
    """The executable shipped in the add-on's zip, or None.  Installing from a zip may drop the
    executable bit (Blender's extension installer extracts with Python's zipfile): restore it."""
    if not os.path.isfile(BUNDLED):
        return None
    if not os.access(BUNDLED, os.X_OK):
        try:
            os.chmod(BUNDLED, os.stat(BUNDLED).st_mode | 0o755)
        except OSError:
            return None
    return BUNDLED if os.access(BUNDLED, os.X_OK) else None


def find_executable(configured=""):
    """(path, where it came from) or (None, why not).  Order: the preference (an override), then
    $FIRMAMENT_EXECUTABLE, then the executable bundled with the add-on, then firmament on PATH."""
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
    bundled = bundled_executable()
    if bundled:
        return bundled, "bundled with the add-on"
    on_path = shutil.which("firmament")
    if on_path:
        return on_path, "PATH"
    if os.path.isfile(BUNDLED):
        return None, "the bundled %s is not executable and its mode could not be changed" % BUNDLED
    return None, "no executable bundled with the add-on, in the preferences, $FIRMAMENT_EXECUTABLE or PATH"

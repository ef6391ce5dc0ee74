"""Firmament Sky: renders physically based skies with the firmament executable and sets them up as
the world, with a matching Sun lamp.  Works as a legacy add-on (Blender 3.4-4.1, bl_info) and as an
extension (4.2+, blender_manifest.toml)."""

bl_info = {
    "name": "Firmament Sky",
    "author": "firmament project",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > World > Firmament Sky; 3D View > Sidebar > Sky",
    "description": "Spectral path-traced skies (date, place, aerosols) with a matching sun lamp",
    "doc_url": "",
    "category": "Lighting",
}

import atexit

import bpy

from . import live, maps, operators, options, panels, preferences, properties

_classes = (preferences.FirmamentSkyPreferences, properties.FirmamentSkySettings) + operators.classes + live.classes + panels.classes


def register():
    try:  # the settings' ranges are the executable's (the bundled one, else $FIRMAMENT_EXECUTABLE, PATH)
        properties.set_ranges(preferences.executable_and_options()[1])
    except (preferences.NotFound, options.OptionsError, AttributeError, KeyError):
        pass  # no executable yet: Generate checks against it when there is one
    for cls in _classes:
        bpy.utils.register_class(cls)
    properties.register()
    bpy.app.handlers.load_pre.append(operators.cancel_running)
    bpy.app.handlers.save_post.append(maps.on_save_post)
    atexit.register(operators.cancel_running)  # quitting Blender ends a running child too
    live.register()


def unregister():
    live.unregister()
    operators.cancel_running()
    atexit.unregister(operators.cancel_running)
    if maps.on_save_post in bpy.app.handlers.save_post:
        bpy.app.handlers.save_post.remove(maps.on_save_post)
    if operators.cancel_running in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(operators.cancel_running)
    properties.unregister()
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)

"""The World-properties panel, the same in a 3D view N-panel tab, and the preset menu."""

import json
import math
import os
import subprocess

import bpy

from . import command, maps, operators, options, preferences, properties, sky_presets


class FIRMAMENT_MT_presets(bpy.types.Menu):
    bl_label = "Sky Presets"
    preset_subdir = operators.PRESET_SUBDIR
    preset_operator = "firmament_sky.load_preset"
    preset_add_operator = "firmament_sky.add_preset"

    def draw(self, context):
        # the shipped presets (read-only, in the add-on) and the user's (presets/firmament_sky/)
        kw = dict(props_default={"menu_idname": self.__class__.__name__},
                  filter_ext=lambda ext: ext.lower() == ".json", display_name=sky_presets.display_name)
        self.path_menu([operators.SHIPPED_PRESETS], self.preset_operator, **kw)
        user = [f for f in bpy.utils.preset_paths(self.preset_subdir) if os.path.isdir(f) and os.listdir(f)]
        if user:
            self.layout.separator()
            self.layout.label(text="Your presets")
            self.path_menu(user, self.preset_operator, **kw)


_sun_cache = {}


def sun_summary(p, context):
    """'Sun 61.2° up, azimuth 183.4°; sunrise 05:13, sunset 21:17' for the date and place, from
    `firmament sun --json` (run once per change of date, time or place), or None."""
    s = properties.to_dict(p)
    key = tuple(s[k] for k in ("year", "month", "day", "hour", "minute", "second", "utc_offset", "latitude",
                               "longitude", "altitude"))
    if key not in _sun_cache:
        try:
            exe = preferences.executable_and_options(context)[0]
            r = subprocess.run(command.sun_arguments(exe, s), capture_output=True, text=True, timeout=10)
            d = json.loads(r.stdout) if r.returncode == 0 else None
            _sun_cache[key] = None if d is None else "Sun %.1f° up, azimuth %.1f°; sunrise %s, sunset %s" % (
                d["elevation_deg"], d["azimuth_deg"], (d.get("sunrise") or "none")[:5], (d.get("sunset") or "none")[:5])
        except (preferences.NotFound, options.OptionsError, OSError, ValueError, KeyError, subprocess.TimeoutExpired):
            _sun_cache[key] = None
        if len(_sun_cache) > 64:
            _sun_cache.pop(next(iter(_sun_cache)))
    return _sun_cache[key]


_aerosol_cache = {}


def aerosol_summary(p, context):
    """(AOD 550, visibility km, cloud optical depth) of the biome, amount, humidity and clouds, from
    `firmament render --print-atmosphere` (no render: milliseconds; run once per change of those), or
    None."""
    s = properties.to_dict(p)
    key = tuple(command.aerosol_options(s) + command.cloud_options(s))
    if key not in _aerosol_cache:
        try:
            exe = preferences.executable_and_options(context)[0]
            r = subprocess.run(command.atmosphere_arguments(exe, s), capture_output=True, text=True, timeout=5)
            d = json.loads(r.stdout) if r.returncode == 0 else None
            _aerosol_cache[key] = None if d is None else (d["aerosol_optical_depth_550nm"], d["visibility_km"],
                                                          d.get("cloud_optical_depth_550nm", 0.0))
        except (preferences.NotFound, options.OptionsError, OSError, ValueError, KeyError, subprocess.TimeoutExpired):
            _aerosol_cache[key] = None
        if len(_aerosol_cache) > 64:
            _aerosol_cache.pop(next(iter(_aerosol_cache)))
    return _aerosol_cache[key]


def _labelled_row(layout, label, props, p):
    """A label on its own line, then the fields with no text of their own: nothing is cut off at
    the sidebar's default width."""
    col = layout.column(align=True)
    col.label(text=label)
    row = col.row(align=True)
    for prop in props:
        row.prop(p, prop, text="")


def draw_clouds(layout, p, context):
    """The cloud layer (type, amount, height) and the fog."""
    col = layout.column(align=True)
    col.prop(p, "cloud_menu")
    if p.cloud != "none":
        col.row(align=True).prop(p, "cloud_amount", expand=True)
        if p.cloud_amount != "DEFAULT":
            col.prop(p, "cloud_tau" if p.cloud_amount == "TAU" else "cloud_lwp")
        col.prop(p, "use_cloud_height")
        if p.use_cloud_height:
            col.prop(p, "cloud_base")
            col.prop(p, "cloud_thickness")
    row = layout.row(align=True)
    row.prop(p, "use_fog")
    sub = row.row()
    sub.enabled = p.use_fog
    sub.prop(p, "fog_visibility", text="")
    if p.cloud != "none" or p.use_fog:
        summary = aerosol_summary(p, context)
        if summary:
            layout.label(text="Cloud optical depth %.2f: the sun's beam x %.2g straight up" % (
                summary[2], math.exp(-summary[2])), icon="LIGHT_SUN")


def draw_settings(layout, context):
    p = context.scene.firmament_sky
    row = layout.row(align=True)
    row.menu("FIRMAMENT_MT_presets", text=FIRMAMENT_MT_presets.bl_label)
    row.operator("firmament_sky.add_preset", text="", icon="ADD")
    row.operator("firmament_sky.add_preset", text="", icon="REMOVE").remove_active = True
    # any preset file, e.g. a job of scenes/thesis/ (its sky)
    row.operator("firmament_sky.load_preset", text="", icon="FILEBROWSER")

    box = layout.box()
    box.prop(p, "sun_source", expand=True)
    if p.sun_source == "TIME":
        _labelled_row(box, "Date (year, month, day)", ("year", "month", "day"), p)
        _labelled_row(box, "Local time (h, min, s)", ("hour", "minute", "second"), p)
        col = box.column(align=True)
        col.prop(p, "utc_offset")
        col.prop(p, "latitude")
        col.prop(p, "longitude")
        info = sun_summary(p, context)
        if info:
            box.label(text=info, icon="LIGHT_SUN")
    else:
        col = box.column(align=True)
        col.prop(p, "sun_elevation")
        col.prop(p, "sun_azimuth")
        col.prop(p, "latitude")

    box = layout.box()
    box.prop(p, "biome_menu")
    if p.biome != "none":
        box.label(text="Aerosol amount as:")
        box.row(align=True).prop(p, "aerosol_amount", expand=True)
        box.prop(p, "turbidity" if p.aerosol_amount == "TURBIDITY" else "aod550")
        aerosol = aerosol_summary(p, context)
        if aerosol:  # visibility: Koschmieder's 3.912 / the extinction at 550 nm at the ground (air + aerosol)
            box.label(text="AOD 550 = %.3f, visibility %.0f km" % aerosol[:2])
        row = box.row(align=True)
        row.prop(p, "use_humidity")
        sub = row.row()
        sub.enabled = p.use_humidity
        sub.prop(p, "humidity", text="")
    draw_clouds(box, p, context)
    box.label(text="Ozone source:")
    box.row(align=True).prop(p, "ozone_mode", expand=True)
    if p.ozone_mode == "MANUAL":
        box.prop(p, "ozone_du")
    box.prop(p, "albedo")
    box.prop(p, "altitude")

    box = layout.box()
    box.prop(p, "resolution")
    box.prop(p, "quality")
    box.prop(p, "sun_mode")
    if p.sun_mode == "LAMP":
        box.prop(p, "camera_disk")
    box.prop(p, "north_offset")
    col = box.column(align=True)
    col.prop(p, "sky_strength")
    col.prop(p, "sun_strength")
    box.prop(p, "ground")
    if p.ground == "COLOUR":
        box.prop(p, "ground_colour")
    row = box.row(align=True)
    row.prop(p, "apply_exposure")
    row.prop(p, "metering", text="")

    running = operators._active["runner"] is not None
    row = layout.row()
    row.scale_y = 1.4
    if running:
        r = operators._active["runner"]
        row.label(text="Rendering: %s %.0f%% (Esc cancels)" % (r.stage, 100 * r.fraction), icon="TIME")
    else:
        row.operator("firmament_sky.generate", icon="WORLD")
    row.prop(p, "live", toggle=True, icon="PLAY")
    if p.last_message:  # one sentence under the button, never a popup over it
        layout.label(text=p.last_message.splitlines()[0], icon="ERROR" if p.last_message.startswith("Error") else "INFO")
    if p.has_result:
        row = layout.row(align=True)
        row.label(text="Suggested exposure %.2f EV" % p.suggested_exposure_ev)
        row.operator("firmament_sky.apply_exposure", text="Apply")

    box = layout.box()
    box.label(text="Bake a Day (one map per frame)", icon="TIME")
    box.row().prop(p, "bake_timing", expand=True)
    col = box.column(align=True)
    col.prop(p, "bake_start")
    col.prop(p, "bake_end")
    if p.bake_timing == "STEP":
        col.prop(p, "bake_step_min")
    else:
        scene = context.scene
        col.label(text="Frames %d-%d: one map per frame" % (scene.frame_start, scene.frame_end))
    box.operator("firmament_sky.bake_day", icon="RENDER_ANIMATION")

    box = layout.box()
    box.prop(p, "keep_maps_with_file")
    box.label(text="Maps: //%s/ beside the .blend" % maps.FOLDER if bpy.data.filepath else
              "Maps: the add-on's folder until the file is saved", icon="FILE_FOLDER")
    row = box.row(align=True)
    row.operator("firmament_sky.pack_maps", icon="PACKAGE")
    row.operator("firmament_sky.clean_maps", text="Clean Unused Maps...", icon="TRASH")


class FIRMAMENT_PT_world(bpy.types.Panel):
    bl_label = "Firmament Sky"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "world"

    def draw(self, context):
        draw_settings(self.layout, context)


class FIRMAMENT_PT_view3d(bpy.types.Panel):
    bl_label = "Firmament Sky"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Sky"

    def draw(self, context):
        draw_settings(self.layout, context)


classes = (FIRMAMENT_MT_presets, FIRMAMENT_PT_world, FIRMAMENT_PT_view3d)

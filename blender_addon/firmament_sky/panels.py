"""The World-properties panel, the same in a 3D view N-panel tab, and the preset menu."""

import os

import bpy

from . import maps, operators, sky_presets


class FIRMAMENT_MT_presets(bpy.types.Menu):
    bl_label = "Sky Presets"
    preset_subdir = operators.PRESET_SUBDIR
    preset_operator = "firmament_sky.load_preset"
    preset_add_operator = "firmament_sky.add_preset"

    def draw(self, context):
        # the shipped presets (read-only, in the add-on) and the user's (presets/firmament_sky/)
        folders = [operators.SHIPPED_PRESETS] + bpy.utils.preset_paths(self.preset_subdir)
        self.path_menu([f for f in folders if os.path.isdir(f)], self.preset_operator,
                       props_default={"menu_idname": self.__class__.__name__},
                       filter_ext=lambda ext: ext.lower() == ".json",
                       display_name=sky_presets.display_name)


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
    col = box.column(align=True)
    if p.sun_source == "TIME":
        row = col.row(align=True)
        row.prop(p, "year")
        row.prop(p, "month")
        row.prop(p, "day")
        row = col.row(align=True)
        row.prop(p, "hour")
        row.prop(p, "minute")
        row.prop(p, "second")
        col.prop(p, "utc_offset")
    else:
        col.prop(p, "sun_elevation")
        col.prop(p, "sun_azimuth")
    col.prop(p, "latitude")
    if p.sun_source == "TIME":
        col.prop(p, "longitude")

    box = layout.box()
    box.prop(p, "biome")
    if p.biome != "none":
        row = box.row(align=True)
        row.prop(p, "aerosol_amount", expand=True)
        box.prop(p, "turbidity" if p.aerosol_amount == "TURBIDITY" else "aod550")
        row = box.row(align=True)
        row.prop(p, "use_humidity")
        sub = row.row()
        sub.enabled = p.use_humidity
        sub.prop(p, "humidity", text="")
    row = box.row(align=True)
    row.prop(p, "ozone_mode", expand=True)
    if p.ozone_mode == "MANUAL":
        box.prop(p, "ozone_du")
    box.prop(p, "albedo")
    box.prop(p, "altitude")

    box = layout.box()
    row = box.row(align=True)
    row.prop(p, "resolution")
    row.prop(p, "quality", text="")
    box.prop(p, "sun_mode")
    box.prop(p, "north_offset")
    box.prop(p, "apply_exposure")

    running = operators._active["runner"] is not None
    row = layout.row()
    row.scale_y = 1.4
    if running:
        r = operators._active["runner"]
        row.label(text="Rendering: %s %.0f%% (Esc cancels)" % (r.stage, 100 * r.fraction), icon="TIME")
    else:
        row.operator("firmament_sky.generate", icon="WORLD")
    if p.has_result:
        row = layout.row(align=True)
        row.label(text="Suggested exposure %.2f EV" % p.suggested_exposure_ev)
        row.operator("firmament_sky.apply_exposure", text="Apply")
    box = layout.box()
    box.label(text="Bake a Day (one map per frame)", icon="TIME")
    row = box.row(align=True)
    row.prop(p, "bake_start")
    row.prop(p, "bake_end")
    row.prop(p, "bake_step_min")
    box.operator("firmament_sky.bake_day", icon="RENDER_ANIMATION")

    box = layout.box()
    box.prop(p, "keep_maps_with_file")
    row = box.row()
    row.label(text="Maps: //%s/ beside the .blend" % maps.FOLDER if bpy.data.filepath else "Maps: the add-on's cache until saved",
              icon="FILE_FOLDER")
    row.operator("firmament_sky.clean_maps", text="Clean Unused", icon="TRASH")
    if p.last_message:
        for line in p.last_message.splitlines()[:3]:
            layout.label(text=line)


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

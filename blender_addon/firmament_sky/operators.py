"""Operators: Generate (modal with a timer in the UI, blocking in background mode), the preset
menu's load / add / remove, and applying the suggested exposure."""

import os
import shutil

import bpy
from bpy.props import StringProperty
from bl_operators.presets import AddPresetBase

from . import command, maps, options, preferences, properties, runner, sky_presets, world

ADDON_DIR = os.path.dirname(os.path.abspath(__file__))
SHIPPED_PRESETS = os.path.join(ADDON_DIR, "presets", "skies")
PRESET_SUBDIR = "firmament_sky"

_active = {"runner": None}  # the one generation in flight (UI mode)


class Job:
    """One generation (series: a baked day): its own folder of maps, removed unless the result is
    applied."""

    def __init__(self, settings, executable, opts, series=False):
        self.settings = settings
        self.series = series
        self.folder = maps.new_folder()
        self.exr = os.path.join(self.folder, "sky.exr")
        self.sidecar = os.path.join(self.folder, "sky.json")
        self.disk = None
        try:
            if series:  # sky_0000.exr, sky_0001.exr, ... each with its sidecar
                args = command.build_series_arguments(executable, opts, settings, self.exr, self.sidecar)
                outputs = []
            else:
                if settings["sun_mode"] == "LAMP_CAMERA_DISK":
                    self.disk = os.path.join(self.folder, "sky_disk.exr")
                args = command.build_arguments(executable, opts, settings, self.exr, self.sidecar, self.disk)
                outputs = [self.exr, self.sidecar] + ([self.disk, os.path.splitext(self.disk)[0] + ".json"] if self.disk else [])
        except command.SettingsError:
            self.discard()
            raise
        self.runner = runner.Runner(args, outputs)

    def frames(self):
        """A finished series' [(exr, sidecar)] in order."""
        n = command.series_plan(self.settings)[3]
        return [(os.path.join(self.folder, "sky_%04d.exr" % i), os.path.join(self.folder, "sky_%04d.json" % i))
                for i in range(n)]

    def discard(self):
        shutil.rmtree(self.folder, ignore_errors=True)


def prepare(context, op, series=False):
    """Validated settings and a Job, or None after reporting why not."""
    settings = properties.to_dict(context.scene.firmament_sky)
    settings["bake_frames"] = context.scene.frame_end - context.scene.frame_start + 1
    try:
        exe, opts = preferences.executable_and_options(context)
        command.validate(settings, opts)
        return Job(settings, exe, opts, series)
    except (preferences.NotFound, options.OptionsError, command.SettingsError, OSError) as e:
        report_error(context, op, str(e))
        return None


def report_error(context, op, message, prefix="Firmament: "):
    """One sentence in Blender's info bar and under the panel's Generate button.  Called from a
    script it is an ERROR (the caller gets a RuntimeError); in the interface a WARNING, since Blender
    pops an ERROR of a cancelled operator up under the mouse, over the button."""
    message = " ".join(message.split())  # one line
    context.scene.firmament_sky.last_message = "Error: " + message
    op.report({"WARNING"} if getattr(op, "_in_ui", False) else {"ERROR"}, prefix + message)


def finish(context, op, job):
    """After the child ended: apply the result or report its error.  Returns the operator result."""
    r = job.runner
    props = context.scene.firmament_sky
    if r.state != runner.Runner.DONE:
        job.discard()
        report_error(context, op, r.error_text(), "Firmament failed (exit %s): " % r.returncode)
        return {"CANCELLED"}
    try:
        if job.series:
            suns = world.apply_series(context.scene, job.settings, job.frames())
            sun, exposure = suns[0], None
        else:
            sun, exposure = world.apply(context.scene, job.settings, job.exr, job.sidecar, job.disk)
    except world.SetupError as e:
        job.discard()
        report_error(context, op, str(e))
        return {"CANCELLED"}
    for img in maps.our_images():  # relative to a saved .blend (the previous maps stay on disk)
        maps.reference(img, bpy.path.abspath(img.filepath))
    props.has_result = True
    ev = world.metered_exposure(sun, job.settings["metering"])
    if ev is not None:
        props.suggested_exposure_ev = ev
    props.aod550_result = sun["aod550"] if sun["aod550"] is not None else -1.0
    seconds = (r.done_event or {}).get("seconds")
    msg = "sun %.2f deg up, azimuth %.2f deg" % (sun["elevation_deg"], sun["azimuth_deg"])
    if job.series:
        msg = "baked %d frames (%d-%d)" % (len(suns), context.scene.frame_start, context.scene.frame_end)
    if seconds is not None:
        msg += ", rendered in %.1f s" % seconds
    if exposure is not None:
        msg += "; film exposure set to %.2f EV" % exposure
    props.last_message = msg
    op.report({"INFO"}, "Firmament: " + msg)
    return {"FINISHED"}


class _Generating:
    """Generate and Bake a Day: a child run modal with a timer in the UI, blocking in background mode."""

    _job = None
    _timer = None
    _in_ui = False
    series = False

    @classmethod
    def poll(cls, context):
        return context.scene is not None and _active["runner"] is None

    def _start(self, context):
        """The prepared job with its child started, or None (reported)."""
        job = prepare(context, self, self.series)
        if job is None:
            return None
        try:
            job.runner.start()
        except OSError as e:
            job.discard()
            report_error(context, self, "cannot run %s: %s" % (job.runner.args[0], e))
            return None
        return job

    def execute(self, context):  # blocking: background mode, scripts
        job = self._start(context)
        if job is None:
            return {"CANCELLED"}
        job.runner.wait()
        return finish(context, self, job)

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        self._in_ui = True
        job = self._start(context)
        if job is None:
            return {"CANCELLED"}
        self._job = job
        _active["runner"] = job.runner
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0.0, 1.0)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def _end(self, context):
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)
        _active["runner"] = None

    def modal(self, context, event):
        r = self._job.runner
        if event.type == "ESC":
            r.cancel()
            self._end(context)
            self._job.discard()
            self.report({"WARNING"}, "Firmament: cancelled; the world was not changed")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        state = r.poll()
        context.window_manager.progress_update(r.fraction)
        if context.workspace is not None:
            context.workspace.status_text_set("Firmament: %s %3.0f%%   (Esc cancels)" % (r.stage, 100.0 * r.fraction))
        for area in context.screen.areas if context.screen else ():
            if area.type in ("PROPERTIES", "VIEW_3D"):
                area.tag_redraw()
        if state == runner.Runner.RUNNING:
            return {"PASS_THROUGH"}
        self._end(context)
        return finish(context, self, self._job)

    def cancel(self, context):  # the window closed or a file is loaded
        if self._job is not None:
            self._job.runner.cancel()
            self._job.discard()
        self._end(context)


class FIRMAMENT_OT_generate(_Generating, bpy.types.Operator):
    """Render the sky with firmament and set it up as the world (and sun lamp)"""
    bl_idname = "firmament_sky.generate"
    bl_label = "Generate Sky"
    bl_options = {"REGISTER", "UNDO"}  # one undo step: the previous world, lamp and exposure with their maps


class FIRMAMENT_OT_bake_day(_Generating, bpy.types.Operator):
    """Render one sky per frame from the start to the end clock time and animate the world (an image
    sequence) and the sun lamp (keyframed per frame); the scene's frame range becomes the day's"""
    bl_idname = "firmament_sky.bake_day"
    bl_label = "Bake a Day"
    bl_options = {"REGISTER", "UNDO"}
    series = True


class FIRMAMENT_OT_load_preset(bpy.types.Operator):
    """Load a sky preset (JSON) into the settings"""
    bl_idname = "firmament_sky.load_preset"
    bl_label = "Load Sky Preset"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    menu_idname: StringProperty(default="FIRMAMENT_MT_presets", options={"SKIP_SAVE", "HIDDEN"})

    def invoke(self, context, event):
        # from the preset menu the file is given; from the panel's folder button the user picks one
        if self.filepath:
            return self.execute(context)
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            d = sky_presets.read(self.filepath, preferences.executable_and_options(context)[1])
        except (sky_presets.PresetError, preferences.NotFound, options.OptionsError) as e:
            self.report({"ERROR"}, "Firmament preset: %s" % e)
            return {"CANCELLED"}
        props = context.scene.firmament_sky
        settings = sky_presets.to_settings(d, properties.defaults())
        properties.assign(props, settings)
        menu = getattr(bpy.types, self.menu_idname, None)
        if menu is not None:
            menu.bl_label = d["name"]
        return {"FINISHED"}


class FIRMAMENT_OT_add_preset(AddPresetBase, bpy.types.Operator):
    """Save the current sky settings as a preset (or remove the active one)"""
    bl_idname = "firmament_sky.add_preset"
    bl_label = "Add Sky Preset"
    preset_menu = "FIRMAMENT_MT_presets"
    preset_subdir = PRESET_SUBDIR
    preset_values = []  # written by add() as JSON, not as Python

    def add(self, context, filepath):
        path = os.path.splitext(filepath)[0] + ".json"
        name = self.name.strip() or os.path.basename(os.path.splitext(filepath)[0])
        opts = preferences.executable_and_options(context)[1]
        sky_presets.write(path, sky_presets.from_settings(name, properties.to_dict(context.scene.firmament_sky)), opts)

    def execute(self, context):
        if self.remove_active or self.remove_name:
            return self._remove(context)
        return super().execute(context)

    def _remove(self, context):
        menu = getattr(bpy.types, self.preset_menu)
        name = menu.bl_label if self.remove_active else self.name
        for folder in bpy.utils.preset_paths(self.preset_subdir):
            for f in os.listdir(folder):
                path = os.path.join(folder, f)
                if f.endswith(".json") and (sky_presets.display_name(path) == name or
                                            os.path.splitext(f)[0] == self.as_filename(name)):
                    os.remove(path)
                    menu.bl_label = "Sky Presets"
                    return {"FINISHED"}
        self.report({"WARNING"}, "Firmament: '%s' is not one of your presets (shipped ones stay)" % name)
        return {"CANCELLED"}


class FIRMAMENT_OT_apply_exposure(bpy.types.Operator):
    """Set the scene's film exposure to the sky's suggested exposure (a white diffuse surface under the
    sky's global horizontal illuminance shows as 1.0)"""
    bl_idname = "firmament_sky.apply_exposure"
    bl_label = "Apply Suggested Exposure"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return context.scene is not None and context.scene.firmament_sky.has_result

    def execute(self, context):
        ev = context.scene.firmament_sky.suggested_exposure_ev
        context.scene.view_settings.exposure = ev
        self.report({"INFO"}, "Firmament: film exposure set to %.2f EV" % ev)
        return {"FINISHED"}


class FIRMAMENT_OT_clean_maps(bpy.types.Operator):
    """Delete the maps that this file does not use, from the add-on's cache and from //firmament/
    beside this .blend (folders another .blend of the same folder names are kept)"""
    bl_idname = "firmament_sky.clean_maps"
    bl_label = "Clean Unused Maps"
    bl_options = {"REGISTER"}

    def invoke(self, context, event):
        return context.window_manager.invoke_confirm(self, event)

    def execute(self, context):
        found = maps.unused()
        for path, _size in found:
            shutil.rmtree(path, ignore_errors=True)
        self.report({"INFO"}, "Firmament: removed %d unused maps (%.1f MB); %s" % (
            len(found), sum(s for _p, s in found) / 1e6, maps.summary()))
        return {"FINISHED"}


class FIRMAMENT_OT_pack_maps(bpy.types.Operator):
    """Pack the world's sky maps into the .blend: the file renders without its //firmament/ folder
    (larger file; Generate Sky makes new, unpacked maps)"""
    bl_idname = "firmament_sky.pack_maps"
    bl_label = "Pack Maps"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return any(img.packed_file is None for img in maps.our_images())

    def execute(self, context):
        unpacked = [img for img in maps.our_images() if img.packed_file is None]
        for img in unpacked:
            img.pack()
        self.report({"INFO"}, "Firmament: packed %d maps into the file (%.1f MB)" % (
            len(unpacked), sum(img.packed_file.size for img in unpacked if img.packed_file) / 1e6))
        return {"FINISHED"}


@bpy.app.handlers.persistent
def cancel_running(*_args):
    """load_pre handler: a new file must not receive the old scene's sky."""
    r = _active["runner"]
    if r is not None:
        r.cancel()
        _active["runner"] = None


classes = (FIRMAMENT_OT_generate, FIRMAMENT_OT_bake_day, FIRMAMENT_OT_load_preset, FIRMAMENT_OT_add_preset, FIRMAMENT_OT_apply_exposure,
           FIRMAMENT_OT_clean_maps, FIRMAMENT_OT_pack_maps)

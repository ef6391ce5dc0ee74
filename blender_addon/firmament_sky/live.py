"""The live sky.  While a scene's Live toggle is on, every change of its sky settings (an edit or a
script: the watch timer, which compares the settings at each pass of Blender's event loop before it
draws; a keyframed value: the frame-change handler; a driven value: the depsgraph-update handler;
undo and redo: their handlers) turns the lamp at once
and asks one `firmament serve` per Blender session for a small preview map: at once when no map is
awaited, else the changes are coalesced by a DEBOUNCE_S timer (the newest wins; the server also
drops a waiting request for a newer one),
and the reply is awaited right there for at most WAIT_S (so that the frame Blender draws next already
shows the new map), else a timer polls for it.  The world's image is swapped
in place when a reply says done, and the lamp takes the reply's strength and colour.  While idle the
server refines its twilight tables and answers the last request again ("refined"): the watch
timer swaps that map in too.

Final renders never use the preview: a render_pre handler renders the final map of the frame's
settings (blocking, as Generate does in background mode) and sets it up before Blender renders,
once per distinct sky (a still renders one map; an animation one per frame whose sky changed)."""

import atexit
import json
import math
import os
import subprocess
import time

import bpy

from . import command, maps, operators, options, preferences, properties, runner, server, sky_presets, world

LIVE_WIDTH = 512  # px; height 256
DEBOUNCE_S = 0.03
RETRY_S = 2.0  # a request refused for want of the executable (or its timing out) is tried again after this
POLL_S = 0.01
# The watch timer runs at every pass of the event loop (a pass is >= 5 ms when Blender is idle): it
# must run in the pass of the edit, before that pass's draw.  The settings have no update callbacks:
# a Python one costs the next draw a re-sync of the whole scene (docs/decisions/2026-12-07-blender-live-latency.md).
WATCH_S = 0.0
# The longest a send waits for its reply before Blender draws (the interface is blocked meanwhile):
# a 512 x 256 preview takes ~20 ms.  Not waited when the last reply's render took longer (clouds, a
# slow machine): a wait that would time out only delays the interface.
# docs/decisions/2026-12-07-blender-live-latency.md
WAIT_S = 0.04
IMAGE_NAME = "Firmament Live Sky"
LIVE_TAG = "firmament_live"  # the live image's custom property (not the maps' TAG: never saved or packed)
FINAL_KEY = "firmament_final_sky"  # the world's custom property: the request of its final map

# the session's one server and what it was last asked
_state = {"server": None, "restarted": False, "scene": None, "pending": False, "last": None,
          "sent": None, "next_id": 1, "rendering": False, "refused": None, "server_s": 0.0, "shown": None,
          "applied": None}
_seen = {}  # scene name -> its LIVE_KEYS' values at the watch's last pass


def live_settings(s):
    """The settings of the preview: the lamp plus the camera's disk unless the disk is in the map."""
    mode = "DISK" if s["sun_mode"] == "DISK" else "LAMP"
    return dict(s, sun_mode=mode, camera_disk=s["camera_disk"] or s["sun_mode"] == "LAMP_CAMERA_DISK")


def request_of(s):
    """The `firmament serve` request (without id and output) for settings s: the preset's keys."""
    d = sky_presets.from_settings("live", s)
    del d["name"]
    if s["biome"] == "none":
        for k in ("turbidity", "aod550", "humidity"):
            d.pop(k, None)
    d.update(width=LIVE_WIDTH, quality="preview")
    if s["sun_mode"] == "DISK":
        d["no_sun_disk"] = False
    else:  # half floats hold the sky without the disk (over 65504): written several times faster
        d.update(no_sun_disk=True, half=True, compression="zip")
    return d


def live_folder():
    path = os.path.join(os.path.dirname(maps.cache_dir()), "live")
    os.makedirs(path, exist_ok=True)
    return path


def server_cache_dir():
    """Built atmospheres: `firmament serve`'s default folder, shared by every Blender session and
    version and the command line (a new session starts warm)."""
    if os.name == "nt":
        base = os.environ.get("LOCALAPPDATA") or os.path.expanduser("~")
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    path = os.path.join(base, "firmament")
    os.makedirs(path, exist_ok=True)
    return path


_sun_cache = {}


def sun_direction(s):
    """(direction +X east +Y north +Z up, elevation in degrees) of the request's sun: the angles, or
    `firmament sun --json` for the date, time and place (milliseconds; cached)."""
    if s["sun_source"] == "TIME":
        key = tuple(s[k] for k in ("year", "month", "day", "hour", "minute", "second", "utc_offset",
                                   "latitude", "longitude", "altitude"))
        if key not in _sun_cache:
            exe = preferences.executable_and_options()[0]
            r = subprocess.run(command.sun_arguments(exe, s), capture_output=True, text=True, timeout=10)
            if r.returncode != 0:
                raise command.SettingsError(r.stderr.strip() or "firmament sun failed")
            d = json.loads(r.stdout)
            _sun_cache[key] = (d["elevation_deg"], d["azimuth_deg"])
            if len(_sun_cache) > 256:
                _sun_cache.pop(next(iter(_sun_cache)))
        el, az = _sun_cache[key]
    else:
        el, az = s["sun_elevation"], s["sun_azimuth"]
    e, a = math.radians(el), math.radians(az)
    return (math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)), el


def report(scene, message):
    """One sentence under the panel's buttons and in the info bar."""
    message = " ".join(str(message).split())
    scene.firmament_sky.last_message = "Error: live sky: " + message
    print("Firmament: live sky: " + message)
    try:
        bpy.ops.firmament_sky.live_report("EXEC_DEFAULT", message="Firmament live sky: " + message)
    except (RuntimeError, AttributeError):
        pass  # no window (background mode): the panel's line and the console have it


def refused_already(scene, req):
    """Whether this request of this scene was refused and reported, and is not yet due a retry."""
    r = _state["refused"]
    return r is not None and r[:2] == (scene.name, req) and (r[2] is None or time.monotonic() < r[2])


def request_update(scene):
    """A sky setting of scene may have changed: if the map depends on it, the lamp turns now and the
    map is asked for now, or when one is awaited, by a DEBOUNCE_S timer that sends the newest.
    Cheap when nothing changed (every depsgraph update asks)."""
    p = scene.firmament_sky
    if not p.live or _state["rendering"]:
        return
    s = live_settings(properties.to_dict(p))
    req = None
    try:
        req = request_of(s)
        if req == _state["last"] and scene.name == _state["scene"]:
            _reshow(scene, s)  # a setting of the world or the lamp only (north, strengths, ground), if any
            return  # nothing the map depends on changed (e.g. a frame without keyframes)
        if refused_already(scene, req):
            return
        exe, opts = preferences.executable_and_options()
        command.validate(s, opts)
        direction, elevation = sun_direction(s)
    except (preferences.NotFound, options.OptionsError, command.SettingsError, OSError, ValueError,
            subprocess.TimeoutExpired) as e:
        # a setting stays refused until it changes; the executable or its preference may come back
        settings_error = isinstance(e, (command.SettingsError, ValueError))
        _state["refused"] = (scene.name, req, None if settings_error else time.monotonic() + RETRY_S)
        report(scene, e)
        return
    if s["sun_mode"] != "DISK":
        world.point_lamp(scene, direction, s["north_offset"], elevation + 0.27 < 0.0,  # the disk's radius
                         cloudless=s["cloud"] == "none" and not s["use_fog"])
    _state.update(scene=scene.name, last=req, pending=True)
    if bpy.app.timers.is_registered(send_pending):
        return  # coalesced: the timer sends the newest
    if _state["sent"] is None:
        send_pending()  # nothing awaited: at once (the writer thread takes it; nothing waits here)
    else:
        bpy.app.timers.register(send_pending, first_interval=DEBOUNCE_S)


def _ensure_server():
    srv = _state["server"]
    if srv is not None and srv.alive():
        return srv
    if srv is not None:  # it died: once restarted, then reported
        why = srv.error_text()
        srv.stop()
        _state["server"] = None
        if _state["restarted"]:
            raise OSError("the firmament server stopped twice: %s" % why)
        _state["restarted"] = True
    exe = preferences.executable_and_options()[0]
    _state["applied"] = None  # a new server answers nothing of the old one's again
    _state["server"] = server.Server(exe, server_cache_dir()).start()
    return _state["server"]


def send_pending():
    """Timer: sends the newest request (two output files in turn: a reply's map is never the one
    being replaced by the next) and awaits its reply for up to WAIT_S, else the poll timer does.
    Returns None: a one-shot timer."""
    if not _state["pending"]:
        return None
    scene = bpy.data.scenes.get(_state["scene"])
    _state["pending"] = False
    if scene is None:
        return None
    try:
        srv = _ensure_server()
    except (OSError, preferences.NotFound, options.OptionsError) as e:
        _give_up(scene, e)
        return None
    rid = _state["next_id"]
    _state["next_id"] += 1
    out = os.path.join(live_folder(), "live_%d.exr" % (rid % 2))
    req = dict(_state["last"], id=rid, output=out)
    _state["sent"] = {"id": rid, "request": req, "settings": live_settings(properties.to_dict(scene.firmament_sky)),
                      "time": time.monotonic()}
    srv.send(req)
    if _state["server_s"] <= WAIT_S and poll(WAIT_S) is None:
        return None  # answered within the bound: applied before Blender draws
    if not bpy.app.timers.is_registered(poll):
        bpy.app.timers.register(poll, first_interval=POLL_S)
    return None


def _give_up(scene, why):
    report(scene, why)
    stop()
    scene.firmament_sky.live = False


def poll(wait_s=0.0):
    """Timer: applies the newest done reply, reports errors, restarts a dead server once; waits up to
    wait_s for the reply (send_pending; the timer waits for nothing).  Returns the next interval
    while a reply is awaited, else None."""
    sent, srv = _state["sent"], _state["server"]
    if sent is None or srv is None:
        return None
    scene = bpy.data.scenes.get(_state["scene"])
    end = time.monotonic() + wait_s
    for reply in _replies(srv, end):
        if reply.get("id") != sent["id"]:
            continue  # superseded, or an older map: a newer one is on its way
        _state["sent"] = None
        _state["server_s"] = reply.get("seconds", 0.0)
        if scene is None:
            return None
        if reply.get("status") == "done":
            _state["applied"] = {"id": sent["id"], "settings": sent["settings"], "refined": reply.get("refined", 0)}
            try:
                apply_reply(scene, reply, sent["settings"])
            except world.SetupError as e:
                report(scene, e)
        elif reply.get("status") == "error":
            report(scene, "%s" % reply.get("message", reply))
        return None
    if not srv.alive():
        _state["last"] = None  # asked again below
        try:
            _ensure_server()
        except OSError as e:
            _give_up(scene, e)
            return None
        _state["server"].send(sent["request"])
    return POLL_S


def take_refined():
    """A map the server made again for the request shown, from twilight tables it refined while
    idle (a reply with the same id and a higher "refined"), replaces it, unless a newer request is
    awaited or due (its map is on its way).  Called by the watch timer: no request, no wait."""
    srv, applied = _state["server"], _state["applied"]
    if srv is None or applied is None or _state["sent"] is not None or _state["pending"]:
        return
    for reply in srv.replies(0.0):
        if (reply.get("id") != applied["id"] or reply.get("status") != "done"
                or reply.get("refined", 0) <= applied["refined"]):
            continue
        scene = bpy.data.scenes.get(_state["scene"])
        if scene is None:
            return
        applied["refined"] = reply["refined"]
        try:
            apply_reply(scene, reply, applied["settings"])
        except world.SetupError as e:
            report(scene, e)


def _replies(srv, end):
    """The server's replies until the monotonic time end (those read already when end is past)."""
    while True:
        got = srv.replies(max(0.0, end - time.monotonic()))
        yield from got
        if not got or time.monotonic() >= end:
            return


def _live_image(path):
    for img in bpy.data.images:
        if img.get(LIVE_TAG):
            if bpy.path.abspath(img.filepath) != path:
                img.filepath = path  # a new path: read from it
            else:
                img.reload()
            return img
    img = world.load_float_image(path, IMAGE_NAME)
    del img[world.TAG]  # not one of the maps a saved file keeps: the preview lives in the cache
    img[LIVE_TAG] = 1
    return img


def apply_reply(scene, reply, settings):
    """A done reply: the world shows its map (its nodes updated in place) and the lamp its sun, with
    the settings it was asked with, or the current ones when they ask for the same map (a change of
    the world's or the lamp's own settings meanwhile)."""
    sun = world.sidecar_fields(reply, "reply %s" % reply.get("id"))
    img = _live_image(reply["output"])
    current = live_settings(properties.to_dict(scene.firmament_sky))
    if request_of(current) == request_of(settings):
        settings = current
    # A reload alone costs EEVEE's draw no world update (its lighting's refresh: 1.3 s of software GL
    # here) and leaving its lighting on the old map is not tried: the world is tagged as a rebuild did
    _show(scene, settings, sun, img).update_tag()
    for window in bpy.context.window_manager.windows if bpy.context.window_manager else ():
        for area in window.screen.areas:
            if area.type == "VIEW_3D":  # the world's nodes and the lamp tag their own updates
                area.tag_redraw()


def _show(scene, settings, sun, img):
    w = world.set_world(scene, settings, sun, img)
    if FINAL_KEY in w:
        del w[FINAL_KEY]
    _state["shown"] = {"scene": scene.name, "settings": settings, "sun": sun}
    return w


def _reshow(scene, settings):
    """Settings that the map does not depend on (north offset, sky and sun strengths, metering, ground,
    camera disk) changed: the world and the lamp follow at once from the map shown, with no request.  A
    map awaited takes the current settings when it comes."""
    shown = _state["shown"]
    if _state["sent"] is not None or shown is None or shown["scene"] != scene.name or shown["settings"] == settings:
        return
    img = next((i for i in bpy.data.images if i.get(LIVE_TAG)), None)
    if img is None:
        return
    try:
        _show(scene, settings, shown["sun"], img)
    except world.SetupError as e:
        report(scene, e)


def watch():
    """Timer, persistent (every pass of the event loop, before Blender draws it): a live scene whose
    sky settings changed since the last pass asks for its map.  Returns WATCH_S."""
    for scene in bpy.data.scenes:
        p = scene.firmament_sky
        if p.live:
            values = properties.live_values(p)
            if _seen.get(scene.name) != values:
                _seen[scene.name] = values
                request_update(scene)
    take_refined()
    return WATCH_S


def settle(timeout_s=60.0):
    """Runs the timers' work (a watch pass, then until the newest request is answered) in background
    mode and tests, where Blender's timers do not run while a script does.  Returns True when nothing
    is awaited."""
    watch()
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        if _state["pending"]:
            send_pending()
        if _state["sent"] is None:
            return True
        if poll() is None and _state["sent"] is None:
            return True
        time.sleep(POLL_S)
    return False


def stop(*_args):
    """Ends the server (toggle off, file load, unregister): no zombie, no orphan."""
    for t in (send_pending, poll):
        if bpy.app.timers.is_registered(t):
            bpy.app.timers.unregister(t)
    _stop_server()


def _stop_server():
    """Also at Python's exit (atexit), when bpy may be gone: nothing of bpy here."""
    srv = _state["server"]
    _state.update(server=None, restarted=False, pending=False, last=None, sent=None, refused=None, server_s=0.0,
                  shown=None, applied=None)
    if srv is not None:
        srv.stop()


def on_live_toggled(self, context):
    if self.live:
        _state.update(last=None, refused=None)
        request_update(self.id_data)
    else:
        stop()


@bpy.app.handlers.persistent
def on_frame_change(scene, _depsgraph=None):
    """Keyframed settings: the sky follows each frame (scrubbing, playing, frame_set)."""
    if scene.firmament_sky.live:
        request_update(scene)


@bpy.app.handlers.persistent
def on_depsgraph_update(scene, _depsgraph=None):
    """Drivers set settings (the driven value is flushed to the scene's own settings before this
    runs): each update compares the request with the last."""
    if scene.firmament_sky.live:
        request_update(scene)


@bpy.app.handlers.persistent
def on_undo_redo(scene, *_args):
    """Undo and redo restore settings, and the world's image from a
    step whose file may hold another map since: the map is asked for again; a restored Live off
    ends the server."""
    live_scene = bpy.data.scenes.get(_state["scene"] or "")
    if _state["server"] is not None and (live_scene is None or not live_scene.firmament_sky.live):
        stop()
    _state["last"] = None
    if scene is not None and scene.firmament_sky.live:
        request_update(scene)


@bpy.app.handlers.persistent
def on_load_pre(*_args):
    stop()


@bpy.app.handlers.persistent
def on_load_post(*_args):
    """A file saved with Live on resumes it: its scenes ask for their maps."""
    for scene in bpy.data.scenes:
        if scene.firmament_sky.live:
            request_update(scene)


@bpy.app.handlers.persistent
def on_render_init(*_args):
    _state["rendering"] = True


@bpy.app.handlers.persistent
def on_render_end(*_args):
    _state["rendering"] = False


@bpy.app.handlers.persistent
def on_render_pre(scene, _depsgraph=None):
    """A render with Live on gets the final map of the frame's settings (once per distinct sky)."""
    if not scene.firmament_sky.live:
        return
    settings = properties.to_dict(scene.firmament_sky)
    if settings["quality"] == "preview":
        settings["quality"] = "final"
    key = json.dumps(settings, sort_keys=True)
    if scene.world is not None and scene.world.get(FINAL_KEY) == key:
        return
    try:
        exe, opts = preferences.executable_and_options()
        command.validate(settings, opts)
        job = operators.Job(settings, exe, opts)
        job.runner.start()
    except (preferences.NotFound, options.OptionsError, command.SettingsError, OSError) as e:
        report(scene, "the final map for the render: %s" % e)
        return
    if job.runner.wait() != runner.Runner.DONE:
        job.discard()
        report(scene, "the final map for the render: %s" % job.runner.error_text())
        return
    try:
        world.apply(scene, settings, job.exr, job.sidecar, job.disk)
    except world.SetupError as e:
        job.discard()
        report(scene, "the final map for the render: %s" % e)
        return
    scene.world[FINAL_KEY] = key


class FIRMAMENT_OT_live_report(bpy.types.Operator):
    """Shows a live-sky message in the info bar (the timers have no operator of their own)"""
    bl_idname = "firmament_sky.live_report"
    bl_label = "Firmament Live Sky Message"
    bl_options = {"INTERNAL"}

    message: bpy.props.StringProperty()

    def execute(self, context):
        self.report({"WARNING"}, self.message)
        return {"FINISHED"}


classes = (FIRMAMENT_OT_live_report,)

_HANDLERS = (("frame_change_post", on_frame_change), ("depsgraph_update_post", on_depsgraph_update),
             ("undo_post", on_undo_redo), ("redo_post", on_undo_redo), ("load_pre", on_load_pre),
             ("load_post", on_load_post), ("render_init", on_render_init), ("render_complete", on_render_end),
             ("render_cancel", on_render_end), ("render_pre", on_render_pre))


def register():
    for name, fn in _HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)
    bpy.app.timers.register(watch, first_interval=WATCH_S, persistent=True)
    atexit.register(_stop_server)  # quitting Blender ends the server too


def unregister():
    stop()
    if bpy.app.timers.is_registered(watch):
        bpy.app.timers.unregister(watch)
    atexit.unregister(_stop_server)
    for name, fn in _HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if fn in handlers:
            handlers.remove(fn)

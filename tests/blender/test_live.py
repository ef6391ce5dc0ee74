"""The live sky (Live toggle): one `firmament serve` per session, the world's image swapped in place
and the lamp turned at once.  Headless Blender runs no timers while a script runs, so the test calls
what the timers call: live.watch, the pass of the event loop after a change (the settings have no
update callbacks), and live.settle (a watch pass, live.send_pending, then live.poll until the reply).

- A setting changed as a script changes it tags no depsgraph update of the scene (a Python update
  callback would, and Blender would re-sync the whole scene at the next draw); a Scene property with
  an update (frame_start) is seen by the same check.

- Live on, the sun's elevation changed: the lamp points at the requested sun within 0.1 degree before
  the reply; after it the world's image is the reply's map: its diffuse horizontal illuminance (the
  upper hemisphere integrated) is the sidecar's within 3%, and its zenith luminance is that of a
  direct `firmament render` of the same request within 3% (preview noise, and the live path's
  interpolation over sun elevations: within 1% of the final path).
- A reply that leaves the world's node structure as it is (the camera's disk on) updates the nodes
  in place: the same node objects (a mark set on each survives), the image the new map, the disk's
  direction the new sun's.  The sky and sun strengths and the north offset (no new map) change the
  world's nodes and the lamp at the next pass, with no request.
- A reply within live.WAIT_S is applied in the change's own handler (before Blender draws); after a
  render longer than the bound, the next change leaves its reply to the poll timer; a server that
  cannot answer (stopped) holds the handler for the bound (at least, and not 3 s more), then the
  timer takes the reply.
- Changes while a map is awaited: only the newest is sent, once.
- A setting the executable refuses is reported once, not at every depsgraph update.
- The server's error reply is reported in one sentence; the next change works.
- Undo and redo (steps pushed right after each edit, as the interface does): the map (its sidecar
  and pixels) and the lamp are those of the restored settings, also when the restored step's
  settings are the current ones; an undone Live off restarts the server, a redone one ends it.
- The elevation keyframed over 5 frames, frame_set on each: lamp and map follow every frame.
- The elevation driven by a frame expression and by an empty's height: lamp and map follow.
- The server refines the deep twilight tables while idle: at -12 the map shown is replaced by the
  same request's refined one (a reply with "refined" 1 or more), with no change of the settings.
- A killed server is restarted once; killed again, the error is reported and Live turns off.
- Toggle off: the server process is gone (reaped: no zombie).
- The sun from a clock time: the lamp at once toward `firmament sun`'s sun, the map's sun the same,
  from the atmosphere already built for the angles on that date (one Earth-Sun distance).
- F12 with Live on renders with a final-quality map of the settings, not the preview, once (a second
  F12 makes none); in 3.4 an animation of keyframed settings renders each frame with its own.
- Opening a file ends the server; a file saved with Live on resumes it."""

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

h.install_and_enable()
live, world = h.submodule("live"), h.submodule("world")
command, properties = h.submodule("command"), h.submodule("properties")
live.LIVE_WIDTH = 128  # CI: a small map (the add-on's is 512 x 256)
scene = bpy.context.scene
p = scene.firmament_sky
p.sun_source, p.biome, p.sun_azimuth, p.sun_elevation = "ANGLES", "rural", 150.0, 20.0
p.camera_disk = False


def lamp_direction():
    lamp = h.sun_lamps()[0]  # its rotation as set (matrix_world waits for the depsgraph)
    return (lamp.rotation_euler.to_matrix() @ Vector((0, 0, 1))).normalized()


def requested_direction():
    e, a = math.radians(p.sun_elevation), math.radians(p.sun_azimuth)
    return Vector((math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)))


def angle_deg(a, b):
    return math.degrees(math.acos(max(-1.0, min(1.0, a.dot(b)))))


def live_image():
    imgs = [i for i in bpy.data.images if i.get(live.LIVE_TAG)]
    h.check(len(imgs) == 1, "one live image: %s" % [i.name for i in imgs])
    env = h.env_of(scene.world.node_tree.nodes[world.NODE_PREFIX + "Sky Background"])
    h.check(env.image == imgs[0], "the world shows the live image")
    return imgs[0]


def rows(img):
    """(zenith luminance: the top row's mean, diffuse horizontal illuminance in lux) of a map."""
    px, (w, hgt) = h.image_pixels(img), img.size
    top = 4 * w * (hgt - 1)
    zenith = sum(h.luminance(px[top + 4 * x:top + 4 * x + 3]) for x in range(w)) / w
    e = 0.0
    for y in range(hgt // 2, hgt):  # rows bottom-up: the upper half is the sky
        theta = (hgt - 0.5 - y) / hgt * math.pi  # zenith angle of the row's centre
        row = sum(h.luminance(px[4 * (y * w + x):4 * (y * w + x) + 3]) for x in range(w)) / w
        e += row * math.cos(theta) * math.sin(theta) * (math.pi / hgt) * 2 * math.pi
    return zenith, 683.0 * e


def direct_zenith(request):
    """Zenith luminance of `firmament render` of the same request (a preset of its keys)."""
    preset = os.path.join(h.OUT, "request.json")
    keys = {k: v for k, v in request.items() if k not in ("id", "output", "width", "quality", "no_sun_disk", "half", "compression")}
    with open(preset, "w") as f:
        json.dump(dict(keys, name="live request"), f)
    out = os.path.join(h.OUT, "direct.exr")
    r = subprocess.run([h.EXE, "render", "--preset", preset, "-o", out, "--width", str(request["width"]),
                        "--quality", "preview", "--no-sun-disk", "--threads", "2"], capture_output=True, text=True)
    h.check(r.returncode == 0, "direct render: %s" % r.stderr.strip())
    img = world.load_float_image(out, "direct")
    z = rows(img)[0]
    bpy.data.images.remove(img)
    return z


def settled(what):
    t0 = time.monotonic()
    h.check(live.settle(120.0), "%s: the reply arrived (%.2f s)" % (what, time.monotonic() - t0))
    h.check(not p.last_message.startswith("Error"), "%s: no error (%s)" % (what, p.last_message or "none"))


# CI: the versions' runs share the built atmosphere (a build takes seconds of CPU; a cache file is
# used only when the library accepts it): seeded from and copied back to $FIRMAMENT_TEST_LIVE_CACHE
shared = os.environ.get("FIRMAMENT_TEST_LIVE_CACHE")


def share(src, dst):
    if not shared:
        return
    os.makedirs(dst, exist_ok=True)
    for f in os.listdir(src):
        d = os.path.join(dst, f)  # a file the server rebuilt (a refused one) replaces the older copy
        if not f.startswith(".") and (not os.path.exists(d) or
                                      os.path.getmtime(os.path.join(src, f)) > os.path.getmtime(d)):
            shutil.copy2(os.path.join(src, f), os.path.join(dst, ".%s.%d" % (f, os.getpid())))  # its mtime too
            os.replace(os.path.join(dst, ".%s.%d" % (f, os.getpid())), os.path.join(dst, f))


if shared and os.path.isdir(shared):
    share(shared, live.server_cache_dir())

# Live on: the first map
p.live = True
settled("Live on")
share(live.server_cache_dir(), shared)
srv = live._state["server"]
h.check(srv is not None and srv.alive(), "one server runs")
pid = srv.pid
img = live_image()
before = rows(img)

# a setting changed as a script changes it (all the live ones, one really) tags no depsgraph update
# of the scene: with a Python update callback it would, and EEVEE would re-sync the whole scene
scene_updates = []


def record_update(_scene, depsgraph):
    scene_updates.append(depsgraph.id_type_updated("SCENE"))


bpy.context.view_layer.update()  # nothing pending
bpy.app.handlers.depsgraph_update_post.append(record_update)
for key in properties.LIVE_KEYS:
    setattr(p, key, tuple(p.ground_colour) if key == "ground_colour" else getattr(p, key))
p.sun_elevation = 35.0
bpy.context.view_layer.update()
h.check(not any(scene_updates), "a script's change of the live settings: no depsgraph update of the scene (%s)"
        % scene_updates)
scene.frame_start = scene.frame_start
bpy.context.view_layer.update()
h.check(any(scene_updates), "the check sees a Scene property with an update (frame_start): %s" % scene_updates)
bpy.app.handlers.depsgraph_update_post.remove(record_update)

# the elevation changed (above): the lamp at the event loop's next pass, before its draw; then the map
live.watch()
h.close(angle_deg(lamp_direction(), requested_direction()), 0.0, 0.1, "lamp toward the requested sun before the reply (deg)")
request = dict(live._state["last"], width=live.LIVE_WIDTH)
settled("elevation 35")
img = live_image()
side = h.sidecar_of(img)
h.close(side["sun"]["elevation_deg"], 35.0, 1e-6, "the map's sun elevation")
h.check(tuple(img.size) == (side["image"]["width"], side["image"]["height"]) == (128, 64),
        "the image is the reply's map: %s" % (tuple(img.size),))
zenith, diffuse = rows(img)
h.check(zenith != before[0], "the world's image changed: zenith %.5g -> %.5g" % (before[0], zenith))
h.close(diffuse / side["sky"]["diffuse_horizontal_illuminance_lux"], 1.0, 0.03,
        "image's diffuse horizontal illuminance / the sidecar's")
h.close(zenith / direct_zenith(request), 1.0, 0.03, "zenith luminance / that of a direct render of the request")
h.close(angle_deg(lamp_direction(), Vector(side["sun"]["direction"])), 0.0, 0.1, "lamp toward the sidecar's sun (deg)")
lamp = h.sun_lamps()[0]
h.close(lamp.data.energy, max(side["sun"]["direct_normal_irradiance_rgb"]), 1e-3 * lamp.data.energy,
        "lamp strength from the reply")
h.check(srv.pid == pid, "the same server")

# a reply that leaves the world's nodes as they are (the camera's disk on: values that follow the sun)
# updates them in place: the same node objects (a mark on each survives), the new map in the image
p.camera_disk = True
settled("the camera's disk on")
nodes = scene.world.node_tree.nodes
ours = sorted(n.name for n in nodes if n.name.startswith(world.NODE_PREFIX))
h.check(world.NODE_PREFIX + "Toward Sun" in ours, "the camera's disk nodes: %s" % ours)
for n in nodes:
    n["firmament_test_mark"] = 1
p.sun_elevation = 36.5
settled("elevation 36.5")
nodes = scene.world.node_tree.nodes
h.check(sorted(n.name for n in nodes if n.name.startswith(world.NODE_PREFIX)) == ours and
        all(n.get("firmament_test_mark") for n in nodes), "a reply of the same structure: the nodes kept, not rebuilt")
side = h.sidecar_of(live_image())
h.close(side["sun"]["elevation_deg"], 36.5, 1e-6, "the nodes kept: the image is the new map")
h.check(rows(live_image())[0] != zenith, "the nodes kept: the image's pixels are the new map's")
h.close(max(abs(a - b) for a, b in zip(nodes[world.NODE_PREFIX + "Toward Sun"].inputs[1].default_value,
                                       side["sun"]["direction"])), 0.0, 1e-6, "the nodes kept: the disk toward the new sun")

# the world's and the lamp's own settings (no new map) follow at once, with no request
sent = live._state["next_id"]
p.sky_strength, p.sun_strength, p.north_offset = 2.0, 0.5, math.radians(30.0)
live.watch()
h.check(live._state["next_id"] == sent and live._state["sent"] is None, "strengths and north: no request")
h.close(nodes[world.NODE_PREFIX + "Sky Background"].inputs["Strength"].default_value, 2.0, 1e-6,
        "the sky strength at once")
h.close(nodes[world.NODE_PREFIX + "North"].inputs["Rotation"].default_value[2],
        world.mapping_rotation_z(p.north_offset, side["image"].get("azimuth_at_center_deg", 90.0)), 1e-6,
        "the north offset at once: the map's rotation")
h.close(angle_deg(lamp_direction(), world.scene_direction(side["sun"]["direction"], p.north_offset)), 0.0, 0.1,
        "the north offset at once: the lamp (deg)")
lamp = h.sun_lamps()[0]
h.close(lamp.data.energy, 0.5 * max(side["sun"]["direct_normal_irradiance_rgb"]), 1e-3 * lamp.data.energy,
        "the sun strength at once")
h.check(all(n.get("firmament_test_mark") for n in nodes), "strengths and north: the nodes kept")
knee = nodes[world.NODE_PREFIX + "Over Knee"].inputs[1].default_value
p.metering = "SKY"  # the camera roll-off's knee follows the metered exposure
live.watch()
h.check(live._state["next_id"] == sent and live._state["sent"] is None, "metering: no request")
h.check(abs(nodes[world.NODE_PREFIX + "Over Knee"].inputs[1].default_value - knee) > 1e-3 * knee,
        "the metering at once: the camera roll-off's knee")
p.metering = "HORIZONTAL"
live.watch()
h.close(nodes[world.NODE_PREFIX + "Over Knee"].inputs[1].default_value, knee, 1e-6 * knee, "the metering back")
p.sky_strength, p.sun_strength, p.north_offset, p.camera_disk = 1.0, 1.0, 0.0, False
settled("strengths, north and disk back")
h.close(angle_deg(lamp_direction(), Vector(side["sun"]["direction"])), 0.0, 0.1, "north back: the lamp (deg)")

# a reply within live.WAIT_S is applied in the change's own handler, so that the frame Blender draws
# next shows it; a bound this long, so that no load on the machine makes the reply miss it
def no_poll_timer():  # headless: a timer registered earlier is never run, so it stays registered
    if bpy.app.timers.is_registered(live.poll):
        bpy.app.timers.unregister(live.poll)


bound = live.WAIT_S
live.WAIT_S = 30.0
no_poll_timer()
p.sun_elevation = 38.0
live.watch()
h.check(live._state["sent"] is None and not bpy.app.timers.is_registered(live.poll),
        "a reply within the bound: nothing awaited once the watch pass returns")
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], 38.0, 1e-6,
        "a reply within the bound: the world shows its map once the watch pass returns")
# after a reply whose render took longer than the bound, the next change does not wait for its reply
live._state["server_s"] = 31.0
no_poll_timer()
p.sun_elevation = 39.0
live.watch()
h.check(live._state["sent"] is not None and bpy.app.timers.is_registered(live.poll),
        "after a render longer than the bound: the reply left to the poll timer")
settled("after a render longer than the bound")
# a reply that cannot come (the server stopped): the handler waits the bound, then the timer takes it
live.WAIT_S, live._state["server_s"] = 0.2, 0.0
os.kill(srv.pid, signal.SIGSTOP)
t0 = time.monotonic()
p.sun_elevation = 34.0
live.watch()
blocked = time.monotonic() - t0
os.kill(srv.pid, signal.SIGCONT)
h.check(live.WAIT_S <= blocked < live.WAIT_S + 3.0 and live._state["sent"] is not None,  # 3 s: a loaded machine
        "no reply within the bound: the watch waited %.3f s (bound %g s), the reply left to the poll timer"
        % (blocked, live.WAIT_S))
settled("the server stopped, then continued")
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], 34.0, 1e-6, "the stopped server's map, once it continued")
live.WAIT_S = bound

# changes while a map is awaited (the bound missed, here by no bound) are coalesced: the newest is
# sent, once
live.WAIT_S = 0.0
first = live._state["next_id"]
for e in (30.0, 31.0, 32.0, 33.0):  # one change per pass, as a drag makes them
    p.sun_elevation = e
    live.watch()
settled("four quick changes")
live.WAIT_S = bound
h.check(live._state["next_id"] - first == 2, "four quick changes: %d requests (the first, then the newest)"
        % (live._state["next_id"] - first))
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], 33.0, 1e-6, "the newest change's map")
p.sun_elevation = 35.0
settled("back to 35")

# the server's error reply: one sentence in the panel's line, Live stays on, the next change works
request_of = live.request_of
live.request_of = lambda settings: dict(request_of(settings), width=3)  # refused by the server
p.sun_elevation = 36.0
settled_ok = live.settle(60.0)
live.request_of = request_of
h.check(settled_ok and p.last_message == "Error: live sky: --width: 3 is outside [8, 16384] pixels" and p.live,
        "the server's error reported: %s" % p.last_message)
p.last_message = ""
p.sun_elevation = 35.0
settled("after an error")
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], 35.0, 1e-6, "after an error: the map follows again")

# a setting the executable refuses: said once, not again at each depsgraph update (which compares)
p.biome = "no-such-biome"
live.watch()
h.check(p.last_message.startswith("Error: live sky:") and "no-such-biome" in p.last_message,
        "a refused biome reported: %s" % p.last_message)
p.last_message = ""
scene.update_tag()
bpy.context.view_layer.update()
live.watch()
h.check(p.last_message == "", "the refused biome not reported again at a depsgraph update or a pass: %s"
        % p.last_message)
p.biome = "rural"

# an executable that cannot be found is not a setting: reported once, and once the preference points
# at one again, the same request is tried again (after live.RETRY_S) with no change of the sky's
prefs = h.preferences()
good = prefs.executable
prefs.executable = "/nonexistent/firmament"
p.sun_elevation = 37.0
live.watch()
h.check("executable" in p.last_message, "a missing executable reported: %s" % p.last_message)
prefs.executable = good
p.last_message = ""
time.sleep(live.RETRY_S + 0.1)
scene.update_tag()  # any later depsgraph update (an edit of anything) tries it again
bpy.context.view_layer.update()
settled("the executable back")
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], 37.0, 1e-6, "the executable back: the refused request made")

# undo and redo, with steps pushed as the interface pushes them: right after an edit, before its map
# is in (a step holds the new settings and lamp, and the image of the map before)
zenith_at = {}
for e in (44.0, 50.0):
    p.sun_elevation = e
    bpy.ops.ed.undo_push(message="elevation %g" % e)
    settled("elevation %g" % e)
    zenith_at[e] = rows(live_image())[0]
p.resolution = 256  # a setting the live map does not use: a step whose live request is the current one
bpy.ops.ed.undo_push(message="width")
for what, op, e in (("undo", bpy.ops.ed.undo, 50.0), ("undo", bpy.ops.ed.undo, 44.0), ("redo", bpy.ops.ed.redo, 50.0)):
    h.check(op() == {"FINISHED"}, what)
    scene = bpy.context.scene  # memfile undo may give the scene a new address
    p = scene.firmament_sky
    h.close(p.sun_elevation, e, 1e-6, "%s: the elevation restored" % what)
    settled("%s to %g" % (what, e))
    side = h.sidecar_of(live_image())
    h.close(side["sun"]["elevation_deg"], e, 1e-6, "%s to %g: the map's sun elevation" % (what, e))
    h.close(rows(live_image())[0] / zenith_at[e], 1.0, 1e-3, "%s to %g: the image is that map (zenith)" % (what, e))
    h.close(angle_deg(lamp_direction(), Vector(side["sun"]["direction"])), 0.0, 0.1, "%s to %g: the lamp (deg)" % (what, e))
pid = live._state["server"].pid
p.live = False
bpy.ops.ed.undo_push(message="Live off")
bpy.ops.ed.undo()
scene, p = bpy.context.scene, bpy.context.scene.firmament_sky
settled("undo of Live off")
h.check(p.live and live._state["server"] is not None and live._state["server"].pid != pid,
        "undo of Live off: a server again")
bpy.ops.ed.redo()
scene, p = bpy.context.scene, bpy.context.scene.firmament_sky
h.check(not p.live and live._state["server"] is None, "redo of Live off: the server is gone")
p.live = True
p.sun_elevation = 35.0
settled("Live on after undo")
pid = live._state["server"].pid

# keyframed elevation over 5 frames
p.keyframe_insert("sun_elevation", frame=1)
p.sun_elevation = 55.0
p.keyframe_insert("sun_elevation", frame=5)
seen = []
for f in range(1, 6):
    scene.frame_set(f)
    h.close(angle_deg(lamp_direction(), requested_direction()), 0.0, 0.1,
            "frame %d: lamp toward the keyframed sun (%.3f deg up) at once" % (f, p.sun_elevation))
    settled("frame %d" % f)
    side = h.sidecar_of(live_image())
    h.close(side["sun"]["elevation_deg"], p.sun_elevation, 1e-3, "frame %d: the map's sun elevation" % f)
    seen.append(rows(live_image())[0])
h.check(len(set(seen)) == 5, "a new map each frame: zenith %s" % ["%.5g" % z for z in seen])
scene.animation_data_clear()

# drivers set the elevation without its update callback: from a frame, and from an empty's height
# (a change the depsgraph update carries)
fc = scene.driver_add("firmament_sky.sun_elevation")
fc.driver.type = "SCRIPTED"
var = fc.driver.variables.new()
var.name, var.type = "z", "SINGLE_PROP"
empty = bpy.data.objects.new("Sun Height", None)
scene.collection.objects.link(empty)
var.targets[0].id, var.targets[0].data_path = empty, "location.z"
fc.driver.expression = "20 + frame + 10 * z"
for what, change, e in (("a frame", lambda: scene.frame_set(7), 27.0),
                        ("an empty's height", lambda: setattr(empty.location, "z", 1.5), 42.0)):
    change()
    bpy.context.view_layer.update()  # what the interface does after an edit
    h.close(p.sun_elevation, e, 1e-4, "driven by %s: the elevation" % what)
    h.close(angle_deg(lamp_direction(), requested_direction()), 0.0, 0.1, "driven by %s: the lamp at once (deg)" % what)
    settled("driven by %s" % what)
    h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], e, 1e-4, "driven by %s: the map's sun elevation" % what)
scene.animation_data_clear()
bpy.data.objects.remove(empty)
scene.frame_set(1)

# the server refines the deep twilight tables while idle and answers the map shown again ("refined"):
# the watch timer reloads the image, with no change of the settings
p.sun_elevation = -12.0
settled("elevation -12")
applied = dict(live._state["applied"])
h.check(applied["refined"] == 0, "-12: the first map from the tables as built (refined %s)" % applied["refined"])
before = list(h.image_pixels(live_image()))
end = time.monotonic() + 300
while live._state["applied"]["refined"] < 1 and time.monotonic() < end:
    live.watch()
    time.sleep(0.05)
h.check(live._state["applied"]["refined"] >= 1 and live._state["applied"]["id"] == applied["id"],
        "a refined map of the same request applied (%s)" % live._state["applied"])
h.check(list(h.image_pixels(live_image())) != before, "the refined map reloaded into the image")
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], -12.0, 1e-6, "the refined map's sun")

# a server that dies is restarted once, then reported
os.kill(pid, signal.SIGKILL)
p.sun_elevation = 40.0
settled("after the server was killed")
srv = live._state["server"]
h.check(srv is not None and srv.alive() and srv.pid != pid, "a new server: %s" % (srv and srv.pid))
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], 40.0, 1e-6, "its map")
pid = srv.pid
os.kill(pid, signal.SIGKILL)
p.sun_elevation = 41.0
live.settle(30.0)
h.check(not p.live and p.last_message.startswith("Error: live sky:") and "stopped twice" in p.last_message,
        "killed again: reported, Live off (%s)" % p.last_message)
h.check(not os.path.exists("/proc/%d" % pid), "the killed server was reaped")

# toggle off stops the server
p.last_message = ""
p.live = True
settled("Live on again")
pid = live._state["server"].pid
p.live = False
h.check(live._state["server"] is None and not os.path.exists("/proc/%d" % pid),
        "Live off: the server (pid %d) is gone" % pid)

# the sun from the date, time and place: the lamp at once from `firmament sun`, then the map's,
# from the atmosphere of the angles on the same date (one Earth-Sun distance: no rebuild)
replies, apply_reply = [], live.apply_reply
live.apply_reply = lambda scene, reply, settings: (replies.append(reply), apply_reply(scene, reply, settings))
p.last_message = ""
p.live = True
p.sun_source, p.hour, p.minute = "TIME", 10, 30
live.watch()
r = subprocess.run(command.sun_arguments(h.EXE, properties.to_dict(p)), capture_output=True, text=True)
sun = json.loads(r.stdout)
e, a = math.radians(sun["elevation_deg"]), math.radians(sun["azimuth_deg"])
expected = Vector((math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)))
h.close(angle_deg(lamp_direction(), expected), 0.0, 0.1, "clock time: lamp toward `firmament sun`'s sun at once (deg)")
settled("clock time")
live.apply_reply = apply_reply
h.check(replies[-1].get("cache") == "memory",  # a new server: its first request, the angles', loaded it
        "a clock time on the angles' date: their atmosphere, in memory (%s)" % replies[-1].get("cache"))
side = h.sidecar_of(live_image())
h.close(angle_deg(Vector(side["sun"]["direction"]), expected), 0.0, 0.1, "clock time: the map's sun is the lamp's (deg)")
p.sun_source = "ANGLES"
settled("angles again")

# F12 with Live on: a final map of the settings, not the preview; a second F12 makes none
p.resolution, p.threads = 32, 2
h.render_settings(scene, res=(8, 8), samples=1)
bpy.ops.render.render()
final = [i for i in h.world_images() if i.users]
h.check(len(final) == 1 and not final[0].get(live.LIVE_TAG), "the render's world map is a generated one")
side = h.sidecar_of(final[0])
h.check(side["parameters"]["quality"] == "final" and side["image"]["width"] == 32,
        "final quality at the set width: %s, %d" % (side["parameters"]["quality"], side["image"]["width"]))
h.close(side["sun"]["elevation_deg"], p.sun_elevation, 1e-3, "the render's map has the settings' sun")
path = final[0].filepath
bpy.ops.render.render()
h.check([i.filepath for i in h.world_images() if i.users] == [path], "a second still render uses the same map")
if h.LEGACY:  # (one version: each final map costs seconds) an animation: each frame's own final map
    p.sun_elevation = 20.0
    p.keyframe_insert("sun_elevation", frame=1)
    p.sun_elevation = 40.0
    p.keyframe_insert("sun_elevation", frame=2)
    scene.frame_start, scene.frame_end = 1, 2
    scene.frame_set(1)
    settled("keyframed for the animation")
    elevations = []
    bpy.app.handlers.render_post.append(lambda sc, *_: elevations.append(
        h.sidecar_of([i for i in h.world_images() if i.users][0])["sun"]["elevation_deg"]))
    scene.render.filepath = os.path.join(h.OUT, "frame_")
    bpy.ops.render.render(animation=True)
    h.check(elevations == [20.0, 40.0], "animation: each frame rendered with its own final map: %s" % elevations)
    scene.animation_data_clear()  # below, the saved file's elevation is the one set, not a keyframe's

# opening a file ends the server; a file saved with Live on resumes it
p.live = True
p.sun_elevation = 27.0
settled("Live on before a file is opened")
pid = live._state["server"].pid
blend = os.path.join(h.OUT, "live.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)
bpy.ops.wm.read_homefile()
h.check(live._state["server"] is None and not os.path.exists("/proc/%d" % pid), "a file opened: the server is gone")
bpy.ops.wm.open_mainfile(filepath=blend)
scene = bpy.context.scene
p = scene.firmament_sky
settled("the file saved with Live on, opened")
h.check(p.live and live._state["server"] is not None and live._state["server"].pid != pid,
        "the file saved with Live on: a new server")
h.close(h.sidecar_of(live_image())["sun"]["elevation_deg"], 27.0, 1e-6, "the file saved with Live on: its map")
p.live = False
h.finish()

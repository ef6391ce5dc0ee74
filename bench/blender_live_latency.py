"""The live sky in a real Blender window (run by bench/blender-live-latency.sh under Xvfb), with the 3D
view in Rendered shading (EEVEE, the scene's world: what a user watching the sky looks at): the time
from a change of the sun elevation property to the world's image reloaded with the new map, and to
the first completed draw of the 3D view after that (the frame that shows the new sky).  The changes
are made one at a time, each once the previous one is drawn, by a script: an assignment from a timer,
which the add-on's watch timer sees in the same pass, before the pass's draw (an edit in the
interface is also seen before the draw, but Blender's own update of the edited Scene property costs
that draw a re-sync of the scene: see the decision log).  Three interleaved kinds, so that the
machine's load is the same for each:
  bounded  the add-on as it is: the reply awaited in the watch pass for up to live.WAIT_S
  timer    live.WAIT_S = 0: the reply taken by the poll timer only (a later event-loop pass)
  no map   the lamp turned by hand (the add-on asks for nothing): what a change costs the window
Lines:
  change -> image reloaded / drawn   median, 90th percentile, largest, per kind
  handler  the time the change took: its assignment and the watch pass that saw it (the interface is
           blocked meanwhile): median, largest
  in pass  how many replies were applied within the watch pass that saw the change
  wait     the change to the request written (0 unless coalesced by the DEBOUNCE_S timer)
  server   the server's own "seconds" (atmosphere found, map rendered, files written)
  pipe     the rest until the reader thread has read the reply (the pipes, JSON)
  poll     the reply read to its being taken (the wait's wake-up, or the poll timer's next run)
  apply    the image reloaded and the world's nodes and lamp set
  draws    the 3D view's draws from the change to the image reloaded, and the process's CPU time
           (all its threads: Mesa's software OpenGL draws in them) from the change to the drawn frame
  3D view  the median time of one draw of the 3D view (its PRE_VIEW to POST_PIXEL callbacks), of
           which a pass of Blender's event loop is mostly made on software OpenGL
  watch    the watch timer's own cost in a pass that saw no change (the main thread's CPU time)
Usage (inside Blender): blender -P bench/blender_live_latency.py -- ZIP EXE OUT [N per kind] [WIDTH] [BOUND_MS]
(BOUND_MS: the bounded kind's live.WAIT_S instead of the add-on's, to try another bound)"""

import math
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "blender"))
import harness as h  # noqa: E402
import bpy  # noqa: E402

N = int(h.argv[3]) if len(h.argv) > 3 else 12
WIDTH = int(h.argv[4]) if len(h.argv) > 4 else 512
BOUND_MS = float(h.argv[5]) if len(h.argv) > 5 else None
KINDS = ("bounded", "timer", "no map")
state = {"phase": "start", "i": 0, "t0": None, "applied": [], "rows": {k: [] for k in KINDS},
         "drawn": [], "pre": None, "view_s": [], "in_handler": False, "applied_in_handler": 0,
         "changed": False, "watch_s": []}


def cpu_s():
    return sum(os.times()[:2])


def pre_view():
    state["pre"] = time.monotonic()


def post_pixel():
    t = time.monotonic()
    state["drawn"].append(t)
    if state["pre"] is not None:
        state["view_s"].append(t - state["pre"])
        state["pre"] = None


def view_3d():
    return next(a for a in bpy.context.window_manager.windows[0].screen.areas if a.type == "VIEW_3D")


def install():
    h.install_and_enable()
    live = h.submodule("live")
    live.LIVE_WIDTH = WIDTH
    state["bound_s"] = live.WAIT_S if BOUND_MS is None else 1e-3 * BOUND_MS
    apply = live.apply_reply

    def timed_apply(scene, reply, settings):  # when the image is in: after the reload
        t = time.monotonic()
        apply(scene, reply, settings)
        state["applied"].append((time.monotonic(), time.monotonic() - t, reply, state["in_handler"]))
    live.apply_reply = timed_apply
    send = live.send_pending

    def timed_send():  # the timer that writes the request (the module's name: the one registered)
        if live._state["pending"]:
            state["sent"] = time.monotonic()
        return send()
    live.send_pending = timed_send
    watch = live.watch

    def timed_watch():  # the change's pass: its time is the handler's; else its own cost per pass
        t, c = time.monotonic(), time.thread_time()
        state["in_handler"] = True
        interval = watch()
        state["in_handler"] = False
        if state["changed"]:
            state["changed"] = False
            state["handler_s"] += time.monotonic() - t
        elif state["phase"] in ("change", "waiting"):
            state["watch_s"].append(time.thread_time() - c)
        return interval
    bpy.app.timers.unregister(live.watch)  # registered by the add-on: the timed one runs instead
    live.watch = timed_watch
    bpy.app.timers.register(timed_watch, first_interval=live.WATCH_S, persistent=True)
    srv = h.submodule("server").Server
    read = srv._read

    def timed_read(self, stream):  # the reader thread: each reply stamped when read from the pipe
        inbox = self._inbox
        put = inbox.put
        inbox.put = lambda reply, *a: put(dict(reply, read_at=time.monotonic()), *a)
        return read(self, stream)
    srv._read = timed_read
    shading = view_3d().spaces[0].shading
    shading.type, shading.use_scene_world_render = "RENDERED", True
    scene = bpy.context.window_manager.windows[0].scene
    scene.render.engine = "BLENDER_EEVEE"
    p = scene.firmament_sky
    p.sun_source, p.biome, p.sun_azimuth, p.sun_elevation = "ANGLES", "rural", 150.0, 20.0
    p.live = True  # the first map: the server starts, the atmosphere is built
    state["phase"], state["t0"] = "warm", time.monotonic()


def change(live, p, kind):
    """One change of the given kind; returns the time its assignment took."""
    live.WAIT_S = 0.0 if kind == "timer" else state["bound_s"]
    state["t0"], state["cpu0"], state["draws0"] = time.monotonic(), cpu_s(), len(state["drawn"])
    state["n_applied"], state["in_handler"] = len(state["applied"]), True
    if kind == "no map":
        h.sun_lamps()[0].rotation_euler[0] += 0.01 * (1 if state["i"] % 2 else -1)
    else:
        p.sun_elevation = 5.0 + (state["i"] * 37 % 60)
    state["in_handler"], state["changed"] = False, True
    return time.monotonic() - state["t0"]


def record(kind):
    """The change's row once its frame is drawn, else None."""
    if kind == "no map":
        t1 = state["t0"]
    elif len(state["applied"]) > state["n_applied"]:
        t1, apply_s, reply, in_handler = state["applied"][-1]
    else:
        return None
    drawn = [t for t in state["drawn"] if t > t1]
    if not drawn:
        return None
    row = {"drawn": drawn[0] - state["t0"], "handler": state["handler_s"], "cpu": cpu_s() - state["cpu0"]}
    if kind != "no map":
        sent = state["sent"]
        row.update(reloaded=t1 - state["t0"], wait=sent - state["t0"], server=reply["seconds"],
                   pipe=reply["read_at"] - sent - reply["seconds"], poll=t1 - apply_s - reply["read_at"],
                   apply=apply_s, in_pass=in_handler, draws=len([t for t in state["drawn"][state["draws0"]:] if t <= t1]))
    return row


def _step():
    if state["phase"] == "start":
        install()
        return 0.005
    live = h.submodule("live")
    p = bpy.context.window_manager.windows[0].scene.firmament_sky
    if state["phase"] == "warm":
        if not state["applied"]:
            if time.monotonic() - state["t0"] > 120:
                raise RuntimeError("no first map in 120 s: %s" % p.last_message)
            return 0.005
        print("first map (server start, atmosphere built): %.3f s" % (state["applied"][0][0] - state["t0"]))
        p.sun_elevation = 21.0  # one map more: the add-on knows how long a map takes (live.WAIT_S)
        state["phase"] = "warm again"
    if state["phase"] == "warm again":
        if len(state["applied"]) < 2:
            return 0.005
        state["phase"] = "change"
        return 0.2
    kind = KINDS[state["i"] % len(KINDS)]
    if state["phase"] == "waiting":
        row = record(kind)
        if row is None:
            if time.monotonic() - state["t0"] > 60:
                raise RuntimeError("no drawn map in 60 s after change %d: %s" % (state["i"], p.last_message))
            return 0.0
        state["rows"][kind].append(row)
        state["i"] += 1
        state["phase"] = "change"
        if state["i"] == N * len(KINDS):
            return report(live)
        kind = KINDS[state["i"] % len(KINDS)]
    state["handler_s"] = change(live, p, kind)
    state["phase"] = "waiting"
    return 0.0


def ms(values, how):
    return 1e3 * (statistics.median(values) if how == "median" else max(values))


def spread(values):
    v = sorted(values)  # p90: the nearest rank
    return "median %.1f ms, p90 %.1f ms, max %.1f ms" % (1e3 * statistics.median(v), 1e3 * v[math.ceil(0.9 * len(v)) - 1], 1e3 * v[-1])


def report(live):
    a = view_3d()
    print("Blender %s, %d x %d preview map, 3D view %d x %d in Rendered shading (EEVEE), %d changes of each kind; "
          "load average %.1f" % (bpy.app.version_string, WIDTH, WIDTH // 2, a.width, a.height, N, os.getloadavg()[0]))
    for kind in KINDS:
        rows = state["rows"][kind]
        col = lambda k: [r[k] for r in rows]  # noqa: E731
        if kind == "bounded":
            title = "bounded wait (live.WAIT_S = %.0f ms%s)" % (1e3 * state["bound_s"], "" if BOUND_MS else ", the add-on's")
        else:
            title = {"timer": "timer only (live.WAIT_S = 0)", "no map": "no map (the lamp turned by hand)"}[kind]
        print("change (%s)" % title)
        if kind != "no map":
            print("  -> image reloaded  %s" % spread(col("reloaded")))
        print("  -> drawn           %s" % spread(col("drawn")))
        print("  handler  median %.1f ms, max %.1f ms; process CPU to the drawn frame median %.0f ms" % (
            ms(col("handler"), "median"), ms(col("handler"), "max"), ms(col("cpu"), "median")))
        if kind != "no map":
            print("  in pass  %d of %d replies applied in the watch pass that saw the change; draws before the reload median %d" % (
                sum(col("in_pass")), len(rows), statistics.median(col("draws"))))
            print("  " + ", ".join("%s %.1f ms" % (k, ms(col(k), "median")) for k in ("wait", "server", "pipe", "poll", "apply")))
    print("  3D view  one draw median %.1f ms" % (1e3 * statistics.median(state["view_s"])))
    w = sorted(state["watch_s"])
    print("  watch    a pass with no change: median %.0f us, p90 %.0f us CPU (%d passes)" % (
        1e6 * statistics.median(w), 1e6 * w[math.ceil(0.9 * len(w)) - 1], len(w)))
    live.stop()
    sys.stdout.flush()
    os._exit(0)


def step():
    try:
        return _step()
    except Exception as e:  # noqa: BLE001 - report and exit
        import traceback
        traceback.print_exc()
        h.submodule("live").stop()
        print("FAIL  %s" % e)
        sys.stdout.flush()
        os._exit(1)


bpy.types.SpaceView3D.draw_handler_add(pre_view, (), "WINDOW", "PRE_VIEW")
bpy.types.SpaceView3D.draw_handler_add(post_pixel, (), "WINDOW", "POST_PIXEL")
bpy.app.timers.register(step, first_interval=0.5)

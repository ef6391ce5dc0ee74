"""The live sky in a real Blender window (run by bench/blender-live-latency.sh under Xvfb): the time
from a change of the sun elevation property to the world's image reloaded with the new map, over
N changes (one at a time, each made once the previous map is in), driven by Blender's own timers as
an artist's drags are.  Prints the median, 90th percentile and largest, and where the time goes:
  wait     the change to the request written (the coalescing timer, DEBOUNCE_S)
  server   the server's own "seconds" (atmosphere found, map rendered, files written)
  pipe     the rest until the reader thread has read the reply (the pipes, JSON)
  poll     the reply read to the poll timer taking it
  apply    the image reloaded and the world's nodes and lamp set
  draws    the 3D view's draws from the change to the image reloaded, and the process's CPU time
           (all its threads: Mesa's software OpenGL draws in them) over the same span
  loop     the period of Blender's event loop meanwhile (a timer asking to run at once: timers run
           once per loop, after the windows' redraws), which the wait and the pipe wait for; and,
           before the first change, the same with only the lamp turned on each pass (Live off:
           what any change costs the window, without the add-on's map)
Usage (inside Blender): blender -P bench/blender_live_latency.py -- ZIP EXE OUT [N] [WIDTH]"""

import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "blender"))
import harness as h  # noqa: E402
import bpy  # noqa: E402

N = int(h.argv[3]) if len(h.argv) > 3 else 20
WIDTH = int(h.argv[4]) if len(h.argv) > 4 else 512
state = {"phase": "start", "i": 0, "t0": None, "applied": [], "rows": [], "ticks": [], "draws": 0}


def cpu_s():
    return sum(os.times()[:2])


def count_draw():
    state["draws"] += 1


def tick():
    state["ticks"].append(time.monotonic())
    return 0.0 if state["phase"] in ("change", "waiting") else None


def _step():
    if state["phase"] == "start":
        h.install_and_enable()
        live = h.submodule("live")
        live.LIVE_WIDTH = WIDTH
        apply = live.apply_reply

        def timed_apply(scene, reply, settings):  # when the image is in: after the reload
            t = time.monotonic()
            apply(scene, reply, settings)
            state["applied"].append((time.monotonic(), time.monotonic() - t, reply))
        live.apply_reply = timed_apply
        send = live.send_pending

        def timed_send():  # the timer that writes the request (the module's name: the one registered)
            if live._state["pending"]:
                state["sent"] = time.monotonic()
            return send()
        live.send_pending = timed_send
        srv = h.submodule("server").Server
        read = srv._read

        def timed_read(self, stream):  # the reader thread: each reply stamped when read from the pipe
            inbox = self._inbox
            put = inbox.put
            inbox.put = lambda reply, *a: put(dict(reply, read_at=time.monotonic()), *a)
            return read(self, stream)
        srv._read = timed_read
        p = bpy.context.window_manager.windows[0].scene.firmament_sky
        p.sun_source, p.biome, p.sun_azimuth, p.sun_elevation = "ANGLES", "rural", 150.0, 20.0
        p.live = True  # the first map: the server starts, the atmosphere is built
        state["phase"], state["t0"] = "warm", time.monotonic()
        return 0.005
    live = h.submodule("live")
    p = bpy.context.window_manager.windows[0].scene.firmament_sky
    if state["phase"] == "warm":
        if not state["applied"]:
            if time.monotonic() - state["t0"] > 120:
                raise RuntimeError("no first map in 120 s: %s" % p.last_message)
            return 0.005
        print("first map (server start, atmosphere built): %.3f s" % (state["applied"][0][0] - state["t0"]))
        p.live = False
        state["phase"], state["t0"] = "lamp", time.monotonic()
    if state["phase"] == "lamp":
        state["ticks"].append(time.monotonic())
        t = state["ticks"]
        if time.monotonic() - state["t0"] < 5.0 or len(t) < 4:
            h.sun_lamps()[0].rotation_euler[0] += 0.001
            return 0.0
        state["lamp_loop"] = statistics.median(b - a for a, b in zip(t, t[1:]))
        state["ticks"] = []
        p.live = True
        state["phase"], state["t0"] = "warm again", time.monotonic()
        return 0.005
    if state["phase"] == "warm again":  # the server started again, the atmosphere from the disk
        if len(state["applied"]) < 2:
            return 0.005
        del state["applied"][0]
        state["phase"] = "change"
        bpy.app.timers.register(tick, first_interval=0.0)
    if state["phase"] == "waiting":
        if len(state["applied"]) < state["i"] + 2:
            if time.monotonic() - state["t0"] > 60:
                raise RuntimeError("no map in 60 s after change %d: %s" % (state["i"], p.last_message))
            return 0.001
        t1, apply_s, reply = state["applied"][-1]
        sent = state["sent"]
        total = t1 - state["t0"]
        state["rows"].append((total, sent - state["t0"], reply["seconds"], reply["read_at"] - sent - reply["seconds"],
                              t1 - apply_s - reply["read_at"], apply_s, state["draws"] - state["draws0"],
                              cpu_s() - state["cpu0"]))
        state["i"] += 1
        state["phase"] = "change"
        if state["i"] == N:
            return report(live)
    # one change, as a drag of the slider makes it
    state["t0"], state["draws0"], state["cpu0"] = time.monotonic(), state["draws"], cpu_s()
    p.sun_elevation = 5.0 + (state["i"] * 37 % 60)
    state["phase"] = "waiting"
    return 0.001


def report(live):
    rows = state["rows"]
    total = sorted(r[0] for r in rows)
    print("Blender %s, %d x %d preview map, %d changes of the sun elevation; load average %.1f" % (
        bpy.app.version_string, WIDTH, WIDTH // 2, len(rows), os.getloadavg()[0]))
    print("change -> image reloaded: median %.1f ms, p90 %.1f ms, max %.1f ms" % (
        1e3 * statistics.median(total), 1e3 * total[int(0.9 * (len(total) - 1))], 1e3 * total[-1]))
    for k, name in enumerate(("wait", "server", "pipe", "poll", "apply"), start=1):
        print("  %-7s median %.1f ms" % (name, 1e3 * statistics.median(r[k] for r in rows)))
    print("  draws   median %d of the 3D view, process CPU median %.1f ms" % (
        statistics.median(r[6] for r in rows), 1e3 * statistics.median(r[7] for r in rows)))
    t = state["ticks"]
    print("  loop    median %.1f ms (only the lamp turned each pass, Live off: %.1f ms)" % (
        1e3 * statistics.median(b - a for a, b in zip(t, t[1:])), 1e3 * state["lamp_loop"]))
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


bpy.types.SpaceView3D.draw_handler_add(count_draw, (), "WINDOW", "POST_PIXEL")
bpy.app.timers.register(step, first_interval=0.5)

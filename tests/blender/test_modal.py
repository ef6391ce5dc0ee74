"""The non-blocking Generate in a real Blender window (under Xvfb): the modal operator with its
timer, Blender's progress, the world applied when the child ends; then a second Generate cancelled
with a simulated Esc (Blender started with --enable-event-simulate): the child is terminated, its
folder removed, the world unchanged.  Runs from timers, since the window exists only after start-up;
the exit status is set with os._exit (exceptions in timers do not reach --python-exit-code)."""

import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import harness as h  # noqa: E402
import bpy  # noqa: E402

state = {"t0": None, "phase": "start", "progress_seen": [], "before": None}


def fail_exit(msg):
    print("FAIL  " + msg)
    sys.stdout.flush()
    os._exit(1)


def snapshot(scene):
    return ([n.name for n in scene.world.node_tree.nodes], [i.filepath for i in h.world_images()],
            [tuple(o.rotation_euler) for o in h.sun_lamps()])


def step():
    try:
        return _step()
    except Exception as e:  # noqa: BLE001 - any error fails the test
        import traceback
        traceback.print_exc()
        fail_exit("exception: %s" % e)


def _step():
    if state["phase"] == "start":
        h.install_and_enable()
    from firmament_sky import maps, operators
    win = bpy.context.window_manager.windows[0]
    scene = win.scene
    if state["phase"] == "start":
        bpy.ops.firmament_sky.load_preset(filepath=h.shipped_preset("golden-hour"))
        # a render of a few seconds (not a 0.3-second preview), so that the timer sees it in progress
        # even when the machine is loaded and the window's timers fire late
        h.fast_settings(scene, width=1024)
        scene.firmament_sky.quality = "final"
        with bpy.context.temp_override(window=win, screen=win.screen, area=win.screen.areas[0]):
            res = bpy.ops.firmament_sky.generate("INVOKE_DEFAULT")
        h.check(res == {"RUNNING_MODAL"}, "Generate runs modal in the UI: %s" % res)
        h.check(operators._active["runner"] is not None, "a runner is in flight")
        h.check(scene.world.node_tree.nodes.get("Firmament Sky") is None, "world not touched while running")
        state["phase"], state["t0"] = "running", time.time()
        return 0.05
    if state["phase"] == "running":
        r = operators._active["runner"]
        if r is not None:
            state["progress_seen"].append(r.fraction)
            if time.time() - state["t0"] > 120:
                fail_exit("the modal Generate did not finish in 120 s")
            return 0.05
        # one intermediate value proves the timer moved the progress; on a loaded machine the
        # timer may fire only a few times during the render, so more is not required
        h.check(len([f for f in state["progress_seen"] if 0 < f < 1]) >= 1,
                "progress updated by the timer: %d values in (0, 1)" % len([f for f in state["progress_seen"] if 0 < f < 1]))
        h.check(scene.world.node_tree.nodes.get("Firmament Sky") is not None and len(h.sun_lamps()) == 1,
                "the world and lamp were set up when the child ended")
        h.check(scene.firmament_sky.last_message.startswith("sun 5.15 deg up"), "result message: %s" % scene.firmament_sky.last_message)
        # second run, cancelled with Esc
        state["before"] = snapshot(scene)
        state["folders"] = sorted(os.listdir(maps.cache_dir()))
        scene.firmament_sky.resolution = 4096
        scene.firmament_sky.quality = "final"
        with bpy.context.temp_override(window=win, screen=win.screen, area=win.screen.areas[0]):
            bpy.ops.firmament_sky.generate("INVOKE_DEFAULT")
        state["runner"] = operators._active["runner"]
        state["phase"], state["t0"] = "to_cancel", time.time()
        return 0.05
    if state["phase"] == "to_cancel":
        r = state["runner"]
        if r.fraction <= 0.0 and time.time() - state["t0"] < 60:
            return 0.05
        h.check(r.fraction > 0.0 and r.state == "running", "second run in progress (%.3f)" % r.fraction)
        win.event_simulate(type="ESC", value="PRESS")
        state["phase"], state["t0"] = "cancelling", time.time()
        return 0.05
    if state["phase"] == "cancelling":
        r = state["runner"]
        if r.state == "running" and time.time() - state["t0"] < 20:
            return 0.05
        h.check(r.state == "cancelled" and r.returncode in (143, -15), "Esc cancelled the child: %s, exit %s" % (r.state, r.returncode))
        h.check(operators._active["runner"] is None, "the modal operator ended")
        h.check(snapshot(scene) == state["before"], "the previous world is untouched")
        h.check(sorted(os.listdir(maps.cache_dir())) == state["folders"], "the cancelled run's folder was removed")
        # the World panel draws (every branch of the settings it shows) without an error
        from firmament_sky import panels
        draws = {"n": 0, "errors": []}
        original = panels.draw_settings

        def counted(layout, context):
            draws["n"] += 1
            try:
                original(layout, context)
            except Exception as e:  # noqa: BLE001 - recorded, then re-raised as Blender would show it
                draws["errors"].append(repr(e))
                raise
        panels.draw_settings = counted
        area = win.screen.areas[0]
        area.type = "PROPERTIES"
        area.spaces.active.context = "WORLD"
        p = scene.firmament_sky
        for sun_source, amount, ozone, ground, timing in (("TIME", "TURBIDITY", "AUTO", "MAP", "STEP"),
                                                          ("ANGLES", "AOD", "MANUAL", "COLOUR", "FRAME_RANGE")):
            p.sun_source, p.aerosol_amount, p.ozone_mode, p.ground, p.bake_timing = sun_source, amount, ozone, ground, timing
            with bpy.context.temp_override(window=win, screen=win.screen, area=area):
                bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=1)
        h.check(draws["n"] >= 2 and not draws["errors"], "the World panel draws: %d draws, errors %s" % (draws["n"], draws["errors"]))
        h.check(panels.sun_summary(p, bpy.context) is None or "sunrise" in panels.sun_summary(p, bpy.context),
                "the panel's sun line: %s" % panels.sun_summary(p, bpy.context))
        p.sun_source = "TIME"
        h.check("sunrise" in (panels.sun_summary(p, bpy.context) or ""), "the sun's position and sunrise before Generate: %s"
                % panels.sun_summary(p, bpy.context))
        # saving in the interface copies the unsaved file's map beside the .blend (the save handler
        # writes the file once more with the relative path)
        blend = os.path.join(h.OUT, "saved", "ui.blend")
        os.makedirs(os.path.dirname(blend))
        with bpy.context.temp_override(window=win, screen=win.screen, area=area):
            bpy.ops.wm.save_as_mainfile(filepath=blend)
        rel = h.world_images()[0].filepath
        h.check(rel.startswith("//firmament/") and os.path.isfile(os.path.join(os.path.dirname(blend), rel[2:])),
                "saved in the interface: the map beside the .blend, relative (%s)" % rel)
        print("%d checks passed, %d failed" % (h._checks["passed"], len(h._checks["failed"])))
        sys.stdout.flush()
        os._exit(1 if h._checks["failed"] else 0)
    return None


bpy.app.timers.register(step, first_interval=1.0)

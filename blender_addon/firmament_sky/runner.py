"""Running the firmament executable: argument lists (never a shell), machine-readable progress,
cancellation.  No bpy here, so that the test suite can drive a Runner directly the way the modal
operator's timer does."""

import json
import os
import queue
import signal
import subprocess
import threading


def executable_name(system=os.name):
    """The executable's file name in the add-on's bin/ (scripts/build-addon): firmament.exe on Windows."""
    return "firmament.exe" if system == "nt" else "firmament"


def parse_progress_line(line):
    """One stdout line of `firmament render --progress json` -> dict, or None for anything else.

    {"event": "progress", "fraction": f, "stage": s} gives fraction clamped to [0, 1]; "done",
    "frame" and "frame_done" events are passed through."""
    line = line.strip()
    if not line.startswith("{"):
        return None
    try:
        event = json.loads(line)
    except ValueError:
        return None
    if not isinstance(event, dict) or not isinstance(event.get("event"), str):
        return None
    if event["event"] == "progress":
        fraction = event.get("fraction")
        if not isinstance(fraction, (int, float)) or isinstance(fraction, bool):
            return None
        event["fraction"] = min(1.0, max(0.0, float(fraction)))
        event["stage"] = str(event.get("stage", ""))
    return event


def terminate(proc, grace_s=3.0):
    """Stops a child of ours and reaps it: SIGTERM (firmament removes its temporary files), then
    SIGKILL after grace_s."""
    if proc.poll() is not None:
        return
    if os.name == "nt":
        # Ctrl-Break, which firmament.exe handles like SIGTERM (it removes its temporary files);
        # Popen's SIGTERM there would be TerminateProcess.  No console to send it through: that.
        try:
            proc.send_signal(signal.CTRL_BREAK_EVENT)
        except OSError:
            proc.terminate()
    else:
        try:
            proc.send_signal(signal.SIGTERM)
        except OSError:  # it ended meanwhile
            pass
    try:
        proc.wait(timeout=grace_s)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


class Runner:
    """One child process.  start() launches it; poll() drains what the reader threads collected
    and returns the state; cancel() terminates it (SIGTERM, then SIGKILL after a grace period) and
    removes the files it was to write.  `outputs` are those files (the executable itself never
    leaves partial files; this also removes complete ones of a cancelled run)."""

    RUNNING, DONE, FAILED, CANCELLED = "running", "done", "failed", "cancelled"

    def __init__(self, args, outputs=()):
        if not isinstance(args, (list, tuple)) or not all(isinstance(a, str) for a in args):
            raise TypeError("arguments must be a list of strings")
        self.args = list(args)
        self.outputs = list(outputs)
        self.fraction = 0.0
        self.stage = "starting"
        self.done_event = None
        self.stderr_lines = []
        self.returncode = None
        self.state = None
        self._proc = None
        self._events = queue.Queue()
        self._threads = []

    def start(self):
        # a session (Windows: a process group) of its own: Blender's own Ctrl-C in a terminal does not
        # reach the child directly, and cancel() can signal the child alone
        group = ({"creationflags": subprocess.CREATE_NEW_PROCESS_GROUP} if os.name == "nt"
                 else {"start_new_session": True})
        self._proc = subprocess.Popen(
            self.args, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True, bufsize=1, **group)
        self.state = self.RUNNING
        for stream, kind in ((self._proc.stdout, "out"), (self._proc.stderr, "err")):
            t = threading.Thread(target=self._read, args=(stream, kind), daemon=True)
            t.start()
            self._threads.append(t)
        return self

    def _read(self, stream, kind):
        for line in stream:
            self._events.put((kind, line.rstrip("\n")))
        stream.close()

    def _drain(self):
        while True:
            try:
                kind, line = self._events.get_nowait()
            except queue.Empty:
                return
            if kind == "err":
                if line.strip():
                    self.stderr_lines.append(line)
                continue
            event = parse_progress_line(line)
            if event is None:
                continue
            if event["event"] == "progress":
                self.fraction = event["fraction"]
                self.stage = event["stage"]
            elif event["event"] == "done":
                self.done_event = event
                self.fraction = 1.0

    def poll(self):
        """Non-blocking: updates fraction/stage/stderr_lines and returns the state."""
        if self.state != self.RUNNING:
            return self.state
        self._drain()
        rc = self._proc.poll()
        if rc is None:
            return self.state
        for t in self._threads:  # the pipes close right after exit
            t.join(timeout=2.0)
        self._drain()
        self.returncode = rc
        self.state = self.DONE if rc == 0 else self.FAILED
        if self.state == self.FAILED:
            self.remove_outputs()
        return self.state

    def wait(self, on_progress=None, interval=0.1):
        """Blocking (background mode): polls until the child ends."""
        while self.poll() == self.RUNNING:
            if on_progress:
                on_progress(self.fraction, self.stage)
            try:
                self._proc.wait(timeout=interval)
            except subprocess.TimeoutExpired:
                pass
        return self.state

    def cancel(self, grace_s=3.0):
        if self.state != self.RUNNING:
            return self.state
        terminate(self._proc, grace_s)
        for t in self._threads:
            t.join(timeout=2.0)
        self._drain()
        self.returncode = self._proc.returncode
        self.state = self.CANCELLED
        self.remove_outputs()
        return self.state

    def remove_outputs(self):
        for path in self.outputs:
            try:
                os.remove(path)
            except FileNotFoundError:
                pass

    def error_text(self):
        """The child's stderr (its one-line message), or the exit status when it said nothing."""
        if self.stderr_lines:
            return self.stderr_lines[-1]  # the executable's one-line message
        return "firmament exited with status %s" % self.returncode

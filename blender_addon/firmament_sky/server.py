"""One `firmament serve` child: requests written as JSON lines by a writer thread, replies read by a
reader thread, so that neither a full pipe nor a slow render ever blocks the caller (Blender's
interface).  No bpy here, so that a test can drive it directly."""

import json
import os
import queue
import subprocess
import threading

from . import runner


class Server:
    """start() launches `executable serve --cache CACHE`; send() queues a request; replies() returns
    the replies read since the last call; stop() ends the child (SIGTERM, then SIGKILL after a grace
    period) and reaps it, so that no zombie or orphan is left."""

    def __init__(self, executable, cache_dir):
        self.args = [executable, "serve", "--cache", cache_dir]
        self.stderr_lines = []
        self._proc = None
        self._inbox = queue.Queue()
        self._outbox = queue.Queue()
        self._threads = []

    @property
    def pid(self):
        return self._proc.pid if self._proc else None

    def start(self):
        # a session of its own (as runner.Runner): Blender's Ctrl-C in a terminal does not reach it
        group = ({"creationflags": subprocess.CREATE_NEW_PROCESS_GROUP} if os.name == "nt"
                 else {"start_new_session": True})
        self._proc = subprocess.Popen(self.args, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True, bufsize=1, **group)
        for target, stream in ((self._read, self._proc.stdout), (self._read_err, self._proc.stderr),
                               (self._write, self._proc.stdin)):
            t = threading.Thread(target=target, args=(stream,), daemon=True)
            t.start()
            self._threads.append(t)
        return self

    def _read(self, stream):
        for line in stream:
            try:
                reply = json.loads(line)
            except ValueError:
                continue
            if isinstance(reply, dict):
                self._inbox.put(reply)
        stream.close()

    def _read_err(self, stream):
        for line in stream:
            if line.strip():
                self.stderr_lines = (self.stderr_lines + [line.rstrip("\n")])[-20:]
        stream.close()

    def _write(self, stream):
        while True:
            line = self._outbox.get()
            if line is None:
                break
            try:
                stream.write(line + "\n")
                stream.flush()
            except (OSError, ValueError):  # the child died: alive() says so
                break
        try:
            stream.close()
        except (OSError, ValueError):
            pass

    def alive(self):
        return self._proc is not None and self._proc.poll() is None

    def send(self, request):
        self._outbox.put(json.dumps(request))

    def replies(self, timeout_s=0.0):
        """The replies read since the last call; when there are none, waits up to timeout_s for one."""
        out = []
        if timeout_s > 0.0:
            try:
                out.append(self._inbox.get(timeout=timeout_s))
            except queue.Empty:
                return out
        while True:
            try:
                out.append(self._inbox.get_nowait())
            except queue.Empty:
                return out

    def error_text(self):
        """Why the child ended: its last line on stderr, else its exit status."""
        if self.stderr_lines:
            return self.stderr_lines[-1]
        rc = self._proc.poll() if self._proc else None
        if rc is not None and rc < 0:
            return "firmament serve was killed by signal %d" % -rc
        return "firmament serve exited with status %s" % rc

    def stop(self, grace_s=3.0):
        if self._proc is None:
            return
        self._outbox.put(None)
        runner.terminate(self._proc, grace_s)  # stops a render at once; no partial file
        for t in self._threads:
            t.join(timeout=2.0)
        self._proc = None

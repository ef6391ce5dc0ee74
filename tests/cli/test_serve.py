#!/usr/bin/env python3
"""`firmament serve` driven as a client drives it (docs/cli.md, "firmament serve").

Usage: test_serve.py path/to/firmament [session|signal|cache|refine ...]   (default: all four)

session  ten requests of one atmosphere (one malformed, one superseded: two sent while the first
         builds the atmosphere, the first of them answered "superseded" and the newest done), then the
         end of the input: every request answered once, in order of completion; each done map is a
         whole EXR (read back by `firmament compare`) with its sidecar, and its sun is the request's
         (given, from the preset's time or from another time of its day): in the EXR header, in the
         sidecar, and in the pixels (close to `firmament render` at that sun, far from it at another
         sun); bad requests are answered with the field and `render`'s own message; the atmosphere is
         built once (into the default cache folder, $XDG_CACHE_HOME/firmament) and then taken from
         memory, without its twilight band until the first sun below 1 degree builds it (the
         replies say so); the input ends while a request renders and another waits: both are answered.
signal   SIGTERM mid-request (its temporary files made, its atmosphere building): exit status
         128 + 15, both requests answered "cancelled", no map, no temporary file, an existing map kept
         as it was; and SIGTERM while idle.
cache    a new server on the session's cache folder takes the atmosphere from the disk (the build's
         and the disk's times printed, not asserted); a truncated cache file is refused, rebuilt and
         replaced whole (the next server takes it from the disk); a byte-flipped one is refused (its
         rebuild stopped by SIGTERM, which leaves no temporary in the folder).  A cache file saved
         before the twilight band (a new folder, a sun of 20) is completed by the next server's
         request at -18: the same pixels, and then the same file bit for bit, as the session's whole
         atmosphere.
refine   a server refining while idle answers its last request at -12 again after a round
         ("refined": 1, a new map); a request by day meanwhile carries no "refined"; the cache file
         holds the round, from which a new server answers with the same map.
Four builds of an atmosphere in all (the session's, the truncated file's, the new folder's, refine's); small
maps at preview quality."""
import json
import math
import os
import queue
import signal
import subprocess
import sys
import tempfile
import threading
import time

FM = os.path.abspath(sys.argv[1])
SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
PARTS = sys.argv[2:] or ["session", "signal", "cache", "refine"]
SMALL = {"quality": "preview", "width": 32}
GOLDEN = {"preset": "golden-hour", **SMALL}  # one atmosphere (its date and place) for the session and the cache
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)
    return ok


class Server:
    """A running `firmament serve`; replies are read by a thread into a queue."""

    def __init__(self, cwd, *args, env=None):
        self.proc = subprocess.Popen([FM, "serve", *args], cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True, env=env)
        self.replies = queue.Queue()
        self.stderr = []
        self.readers = [threading.Thread(target=self._read, args=(self.proc.stdout, self.replies.put), daemon=True),
                        threading.Thread(target=self._read, args=(self.proc.stderr, self.stderr.append), daemon=True)]
        for t in self.readers:
            t.start()

    @staticmethod
    def _read(stream, put):
        for line in stream:
            put(line)

    def send(self, request):
        self.proc.stdin.write((request if isinstance(request, str) else json.dumps(request)) + "\n")
        self.proc.stdin.flush()

    def reply(self, timeout=120):
        line = self.replies.get(timeout=timeout)
        return json.loads(line)  # every reply is one JSON object on one line

    def rest(self):
        """The replies not read yet, once the server has ended (its output read to the end)."""
        for t in self.readers:
            t.join(timeout=30)
        rest = []
        while not self.replies.empty():
            rest.append(json.loads(self.replies.get()))
        return rest

    def finish(self, timeout=120):
        self.proc.stdin.close()
        code = self.proc.wait(timeout=timeout)
        return code, self.rest()


def direction(elevation, azimuth):
    e, a = math.radians(elevation), math.radians(azimuth)
    return [math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)]


def header(path):
    """`firmament info`: the EXR header as {name: value text}."""
    out = subprocess.run([FM, "info", path], capture_output=True, text=True)
    check(out.returncode == 0, f"firmament info {path}: {out.stderr.strip()}")
    return dict(line.split(" (", 1)[0:1] + [line.split("): ", 1)[1]] for line in out.stdout.splitlines()
                if "): " in line)


def compare(a, b):
    out = subprocess.run([FM, "compare", a, b, "--json", "--exclude-sun", "3"], capture_output=True, text=True)
    check(out.returncode == 0, f"compare {a} {b}: {out.stderr.strip()}")
    return json.loads(out.stdout) if out.returncode == 0 else {"rms": math.inf, "pixels": 0}


def leftovers(folder, expected):
    """Files in folder other than the expected ones (temporaries, partial maps)."""
    return sorted(set(os.listdir(folder)) - set(expected))


def band_sequence(replies, elevations):
    """The twilight band (every sun below the horizon) through a server's done replies in order
    (their suns' elevations): pending until the first sun below 1 degree, built by it, then ready."""
    want, seen = [], "pending"
    for e in elevations:
        if seen == "pending" and e < 1:
            want.append("built")
            seen = "ready"
        else:
            want.append(seen)
    got = [r.get("twilight_band") for r in replies]
    check(got == want, f"twilight band by request (suns {elevations}): {got}, expected {want}")


def check_done(reply, folder, elevation, azimuth, width=32, colorspace="Linear Rec.709"):
    """A done reply: the map and sidecar exist, the map reads back whole, its sun is the request's."""
    if not check(reply.get("status") == "done", f"{reply.get('id')}: done, not {reply}"):
        return
    exr, sidecar = os.path.join(folder, reply["output"]), os.path.join(folder, reply["sidecar"])
    check(os.path.isfile(exr) and os.path.isfile(sidecar), f"{reply['id']}: {exr} and {sidecar} exist")
    with open(sidecar) as f:
        side = json.load(f)
    check(side["sun"] == reply["sun"] and side["image"] == reply["image"],
          f"{reply['id']}: the reply holds the sidecar's fields")
    check(side["image"]["width"] == width and side["image"]["colorspace"] == colorspace,
          f"{reply['id']}: sidecar image {side['image']['width']} wide in {side['image']['colorspace']}")
    want = direction(elevation, azimuth)
    got = side["sun"]["direction"]
    check(max(abs(g - w) for g, w in zip(got, want)) < 1e-6,
          f"{reply['id']}: sidecar sun direction {got}, requested {want} (elevation {elevation}, azimuth {azimuth})")
    h = header(exr)
    check(abs(float(h.get("firmament.sun.elevation_deg", "nan")) - elevation) < 1e-6,
          f"{reply['id']}: EXR header sun elevation {h.get('firmament.sun.elevation_deg')} = {elevation}")
    whole = compare(exr, exr)
    check(whole["pixels"] > 0.9 * width * width / 2, f"{reply['id']}: {exr} reads back whole ({whole['pixels']} px)")
    stages = reply.get("stage_seconds", {})
    check(set(stages) == {"atmosphere", "render", "write"} and all(v >= 0 for v in stages.values())
          and abs(sum(stages.values()) - reply.get("seconds", -1)) < 1e-3,
          f"{reply['id']}: seconds {reply.get('seconds')} = the sum of stage_seconds {stages}")


def cli_render(folder, name, elevation, azimuth):
    """`firmament render` of the session's sky at a sun."""
    path = os.path.join(folder, name)
    out = subprocess.run([FM, "render", "--preset", "golden-hour", "--quality", "preview", "--width", "32",
                          "--sun-elevation", str(elevation), "--sun-azimuth", str(azimuth), "-o", path, "--progress",
                          "none"], capture_output=True, text=True)
    check(out.returncode == 0, f"render {name}: {out.stderr.strip()}")
    return path


def sun_of(date, clock, utc_offset, latitude, longitude):
    """`firmament sun --json` (six decimals of a degree: 1e-8 in a direction's components)."""
    out = subprocess.run([FM, "sun", "--date", date, "--time", clock, "--utc-offset", utc_offset, "--latitude",
                          str(latitude), "--longitude", str(longitude), "--json"], capture_output=True, text=True)
    return json.loads(out.stdout)


def cli_message(*args):
    """The one line `firmament render` prints for a bad option, without its "firmament: "."""
    out = subprocess.run([FM, "render", *args, "--progress", "none", "-o", os.devnull + ".exr"],
                         capture_output=True, text=True)
    check(out.returncode == 2, f"render {args}: exit 2")
    return out.stderr.strip().removeprefix("firmament: ")


# ---- a session of ten requests --------------------------------------------------------------------

def session(tmp, xdg):
    """Every request of the session is of one atmosphere (golden-hour's: its date and place), built
    once by request 1 into the default cache folder under xdg."""
    with open(os.path.join(SOURCE, "presets", "skies", "golden-hour.json")) as f:
        golden = json.load(f)
    # no refinement: its replies would come between the session's whenever a round ends (refine below)
    srv = Server(tmp, "--threads", "2", "--refine", "0", env={**os.environ, "XDG_CACHE_HOME": xdg})
    # 1: the atmosphere is built (seconds), then the map rendered; 2 and 3 arrive while it builds
    srv.send({"id": 1, "output": "r1.exr", **GOLDEN, "sun_elevation": 10, "sun_azimuth": 180})
    time.sleep(0.3)  # the server has taken request 1
    srv.send({"id": 2, "output": "r2.exr", **GOLDEN, "sun_elevation": 20, "sun_azimuth": 90})
    srv.send({"id": "three", "output": "r3.exr", **GOLDEN, "sun_elevation": 35, "sun_azimuth": 250})
    replies = [srv.reply(timeout=300) for _ in range(3)]
    ids = [r.get("id") for r in replies]
    check(ids == [2, 1, "three"], f"replies to 1, 2, 3 in the order 2 (superseded), 1, three: {ids}")
    by_id = {r.get("id"): r for r in replies}
    check(by_id.get(2, {}).get("status") == "superseded", f"request 2 superseded: {by_id.get(2, {}).get('status')}")
    check(not os.path.exists(os.path.join(tmp, "r2.exr")), "no map for the superseded request")
    check_done(by_id.get(1, {}), tmp, 10, 180)
    check_done(by_id.get("three", {}), tmp, 35, 250)
    check(by_id.get(1, {}).get("cache") == "built", f"request 1 built its atmosphere: {by_id.get(1, {}).get('cache')}")
    check(by_id.get("three", {}).get("cache") == "memory", "request three took the atmosphere from memory")
    # the map's sun in its pixels: close to `render` at that sun, far from `render` at another
    same = compare(os.path.join(tmp, "r3.exr"), cli_render(tmp, "cli_same.exr", 35, 250))
    other = compare(os.path.join(tmp, "r3.exr"), cli_render(tmp, "cli_other.exr", 35, 70))
    print(f"r3 against render at its sun: rms {same['rms']:.4f}; at another azimuth: rms {other['rms']:.4f}")
    check(same["rms"] < 0.1 and other["rms"] > 0.3, f"r3's pixels follow its sun: {same['rms']}, {other['rms']}")

    # 4: not JSON; 5: a value out of range; 6: an unknown key; 7: an unknown biome -- each answered,
    # the server goes on
    srv.send("{this is not json")
    r = srv.reply()
    check(r.get("status") == "error" and r.get("id") is None and "line 4" in r.get("message", ""),
          f"malformed line answered: {r}")
    srv.send({"id": 5, "output": "r5.exr", "sun_elevation": 95, **SMALL})
    r = srv.reply()
    check(r.get("status") == "error" and r.get("field") == "sun_elevation" and r.get("id") == 5
          and r.get("message") == cli_message("--sun-elevation", "95"), f"out-of-range value answered as render: {r}")
    srv.send({"id": 6, "output": "r6.exr", "turbidty": 2, **SMALL})
    r = srv.reply()
    check(r.get("status") == "error" and r.get("field") == "turbidty", f"unknown key named: {r}")
    srv.send({"id": 7, "output": "r7.exr", "biome": "nowhere", **SMALL})
    r = srv.reply()
    check(r.get("status") == "error" and r.get("field") == "biome"
          and r.get("message") == cli_message("--biome", "nowhere"), f"unknown biome answered as render: {r}")

    # 8: the preset's own sun, from its time.  The time of day is no part of the atmosphere: from memory.
    srv.send({"id": 8, "output": "r8.exr", **GOLDEN})
    sun8 = sun_of(golden["date"], golden["time"], golden["utc_offset"], golden["latitude"], golden["longitude"])
    r8 = srv.reply()
    check_done(r8, tmp, sun8["elevation_deg"], sun8["azimuth_deg"])
    check(r8.get("cache") == "memory", f"8 from memory: {r8.get('cache')}")

    # 9: another time of the preset's day, ACEScg, a sidecar of its own name, and a larger map (a
    # second or so to render and write); 10 arrives while 9 is under way, and the input ends: both
    # are answered, then the server exits 0
    srv.send({"id": 9, "output": "r9.exr", "sidecar": "r9-sky.json", "colorspace": "ACEScg", "time": "20:45",
              **GOLDEN, "width": 2048})
    time.sleep(0.1)  # the server has taken request 9
    srv.send({"id": 10, "output": "r10.exr", **GOLDEN, "sun_elevation": -5, "sun_azimuth": 270})
    code, rest = srv.finish()
    check(code == 0, f"exit status 0 at the end of the input, not {code}: {''.join(srv.stderr)}")
    ids = [r.get("id") for r in rest]
    check(ids == [9, 10], f"requests 9 and 10 answered after the end of the input: {ids}")
    if ids == [9, 10]:
        r9 = rest[0]
        check(r9.get("sidecar") == "r9-sky.json", f"the request's sidecar name: {r9.get('sidecar')}")
        sun9 = sun_of(golden["date"], "20:45", golden["utc_offset"], golden["latitude"], golden["longitude"])
        check_done(r9, tmp, sun9["elevation_deg"], sun9["azimuth_deg"], width=2048, colorspace="ACEScg")
        check_done(rest[1], tmp, -5, 270)
        check(r9.get("cache") == "memory" and rest[1].get("cache") == "memory", "9 and 10 from memory")
        band_sequence([by_id.get(1, {}), by_id.get("three", {}), r8, r9, rest[1]],
                      [10, 35, sun8["elevation_deg"], sun9["elevation_deg"], -5])
    expected = ["r1.exr", "r1.json", "r3.exr", "r3.json", "r8.exr", "r8.json", "r9.exr", "r9-sky.json",
                "r10.exr", "r10.json", "cli_same.exr", "cli_same.json", "cli_other.exr", "cli_other.json"]
    check(not leftovers(tmp, expected), f"nothing else written: {leftovers(tmp, expected)}")
    return by_id.get(1, {}).get("seconds")


# ---- signals ----------------------------------------------------------------------------------------

def signals(tmp):
    out = os.path.join(tmp, "out")
    os.mkdir(out)
    with open(os.path.join(out, "kept.exr"), "w") as f:
        f.write("an existing map")
    srv = Server(out, "--no-cache")
    # the request's temporary files are made first, then its atmosphere is built (a second or more):
    # the signal comes during that build
    srv.send({"id": "long", "output": "kept.exr", "width": 512, "turbidity": 3})
    deadline = time.monotonic() + 60
    while not any(n.startswith(".kept.exr.") for n in os.listdir(out)) and time.monotonic() < deadline:
        time.sleep(0.01)
    check(time.monotonic() < deadline, "the request's temporary files appeared")
    srv.send({"id": "new", "output": "new.exr", "width": 512, "turbidity": 3})  # waits: cancelled too
    time.sleep(0.3)
    srv.proc.send_signal(signal.SIGTERM)
    code = srv.proc.wait(timeout=60)
    check(code == 128 + signal.SIGTERM, f"SIGTERM mid-render: exit {code}, not {128 + signal.SIGTERM}")
    replies = srv.rest()
    check(all(r.get("status") == "cancelled" for r in replies) and len(replies) == 2,
          f"both requests answered cancelled: {replies}")
    check(leftovers(out, ["kept.exr"]) == [], f"no map and no temporary: {os.listdir(out)}")
    with open(os.path.join(out, "kept.exr")) as f:
        check(f.read() == "an existing map", "the existing map is kept")

    idle = Server(out, "--no-cache")
    time.sleep(0.3)
    idle.proc.send_signal(signal.SIGTERM)
    code = idle.proc.wait(timeout=10)
    check(code == 128 + signal.SIGTERM, f"SIGTERM while idle: exit {code}")


# ---- the disk cache ---------------------------------------------------------------------------------

def one_map(tmp, folder, name, elevation):
    """A server on the cache folder that renders one map of the session's sky and ends: (reply,
    seconds from start to reply, stderr)."""
    start = time.monotonic()
    srv = Server(tmp, "--cache", folder, "--threads", "2")
    srv.send({"id": name, "output": name + ".exr", **GOLDEN, "sun_elevation": elevation, "sun_azimuth": 180})
    code, rest = srv.finish(timeout=300)
    seconds = time.monotonic() - start
    check(code == 0 and len(rest) == 1, f"{name}: exit {code}, replies {rest}")
    reply = rest[0] if rest else {}
    check_done(reply, tmp, elevation, 180)
    return reply, seconds, "".join(srv.stderr)


def same_bytes(a, b):
    with open(a, "rb") as f, open(b, "rb") as g:
        return f.read() == g.read()


def check_same_pixels(a, b, what):
    """Check that two maps have the same pixels (the whole map, sun included)."""
    out = subprocess.run([FM, "compare", a, b, "--json"], capture_output=True, text=True)
    same = json.loads(out.stdout) if out.returncode == 0 else {}
    check(same.get("pixels", 0) > 0 and same.get("rms") == 0 and same.get("max") == 0,
          f"{what}: {same or out.stderr}")


def twilight_band_completes_file(tmp, folder):
    """folder holds the session's whole atmosphere (or none: then the first server here builds it
    whole, the twilight band too).  A new folder: its file saved by a request at 20 without the
    band, then completed by the next server's at -18."""
    whole, _, _ = one_map(tmp, folder, "whole18", -18)
    check(whole.get("twilight_band") in ("ready", "built"), f"-18 from the whole atmosphere: {whole}")
    lazy = os.path.join(tmp, "lazy-cache")
    day, _, _ = one_map(tmp, lazy, "lazy20", 20)
    check(day.get("cache") == "built" and day.get("twilight_band") == "pending",
          f"a sun of 20: built without the twilight band ({day.get('cache')}, {day.get('twilight_band')})")
    files = os.listdir(lazy)
    if not check(len(files) == 1, f"one cache file: {files}"):
        return
    saved = os.path.join(lazy, files[0])
    before = open(saved, "rb").read()
    deep, _, _ = one_map(tmp, lazy, "lazy18", -18)
    check(deep.get("cache") == "disk" and deep.get("twilight_band") == "built",
          f"-18 from the file without the band: built it ({deep.get('cache')}, {deep.get('twilight_band')})")
    check_same_pixels(os.path.join(tmp, "lazy18.exr"), os.path.join(tmp, "whole18.exr"),
                      "the map at -18 from the completed file has the whole atmosphere's pixels")
    check(open(saved, "rb").read() != before and os.listdir(lazy) == files,
          f"the cache file replaced by one with the band: {os.listdir(lazy)}")
    whole_file = [f for f in os.listdir(folder) if f == files[0]]
    check(whole_file and same_bytes(saved, os.path.join(folder, files[0])),
          "the completed cache file is the whole atmosphere's, bit for bit")
    again, _, _ = one_map(tmp, lazy, "lazy10", -10)
    check(again.get("cache") == "disk" and again.get("twilight_band") == "ready",
          f"the next server finds the band in the file ({again.get('cache')}, {again.get('twilight_band')})")


def cache(tmp, folder, built_seconds):
    """folder: the session's default cache folder, holding its atmosphere (or none, when the session
    did not run: then the first server here builds it)."""
    twilight_band_completes_file(tmp, folder)
    first, t_first, _ = one_map(tmp, folder, "c1", 20)
    if first.get("cache") == "built":
        built_seconds = first.get("seconds")
        first, t_first, _ = one_map(tmp, folder, "c2", 40)
    files = os.listdir(folder) if os.path.isdir(folder) else []
    check(len(files) == 1 and len(files[0].split(".")[0]) == 32, f"one cache file named by its key: {files}")
    print(f"a request that built the atmosphere: {built_seconds} s; a new server's first request with it "
          f"on the disk: {first.get('seconds')} s ({t_first:.2f} s from the server's start)")
    check(first.get("cache") == "disk", f"a new server takes the atmosphere from the disk: {first.get('cache')}")
    if len(files) != 1:
        return
    path = os.path.join(folder, files[0])
    size = os.path.getsize(path)

    # truncated: refused, rebuilt, replaced whole; the next server takes the new file
    with open(path, "r+b") as f:
        f.truncate(size // 2)
    reply, _, err = one_map(tmp, folder, "truncated", 30)
    check(reply.get("cache") == "built", f"truncated cache file rebuilt, not used: {reply.get('cache')}")
    check("refused" in err, f"truncated cache file: stderr says it was refused: {err.strip()}")
    check(os.path.getsize(path) == size, f"truncated cache file replaced whole ({os.path.getsize(path)} bytes)")
    again, _, _ = one_map(tmp, folder, "replaced", 25)
    check(again.get("cache") == "disk", f"after the truncated file was replaced: from the disk ({again.get('cache')})")

    # bytes flipped: refused too (its rebuild is the truncated file's: stopped here by SIGTERM, which
    # leaves no temporary in the folder)
    with open(path, "r+b") as f:
        data = bytearray(f.read())
        for i in (len(data) // 3, len(data) // 2, len(data) - 9):
            data[i] ^= 0x5A
        f.seek(0)
        f.write(data)
    srv = Server(tmp, "--cache", folder)
    srv.send({"id": "flipped", "output": "flipped.exr", **GOLDEN, "sun_elevation": 30})
    deadline = time.monotonic() + 120
    while not any("refused" in line for line in srv.stderr) and srv.replies.empty() and time.monotonic() < deadline:
        time.sleep(0.02)
    srv.proc.send_signal(signal.SIGTERM)
    code = srv.proc.wait(timeout=120)
    rest = srv.rest()
    check(any("refused" in line for line in srv.stderr), f"byte-flipped cache file refused: {''.join(srv.stderr)}")
    check(not any(r.get("status") == "done" for r in rest), f"no map from the byte-flipped file: {rest}")
    check(code == 128 + signal.SIGTERM, f"SIGTERM during the rebuild: exit {code}")
    check(sorted(os.listdir(folder)) == files, f"no temporary left in the cache: {os.listdir(folder)}")


# ---- refinement while idle ----------------------------------------------------------------------

def refine(tmp):
    """A server allowed one round of refinement: a map by day (no "refined" in its reply: it does not
    read the twilight band), then -12 (the band built, refined 0), then, with no request waiting,
    the round and the same request answered again (refined 1) with a map that changed.  The cache
    file holds the round: a new server answers -12 from the disk with refined 1 and the same pixels."""
    folder = os.path.join(tmp, "cache")
    srv = Server(tmp, "--cache", folder, "--threads", "2", "--refine", "1")
    srv.send({"id": "day", "output": "day.exr", **GOLDEN, "sun_elevation": 10, "sun_azimuth": 180})
    day = srv.reply(timeout=300)
    check_done(day, tmp, 10, 180)
    check("refined" not in day, f"a map by day does not read the twilight band: {day}")
    srv.send({"id": "deep", "output": "deep.exr", **GOLDEN, "sun_elevation": -12, "sun_azimuth": 180})
    first = srv.reply(timeout=300)
    check_done(first, tmp, -12, 180)
    check(first.get("twilight_band") == "built" and first.get("refined") == 0,
          f"-12: the band built, not refined yet ({first.get('twilight_band')}, {first.get('refined')})")
    before = open(os.path.join(tmp, "deep.exr"), "rb").read()
    refined = srv.reply(timeout=300)
    check(refined.get("id") == "deep" and refined.get("status") == "done" and refined.get("refined") == 1,
          f"-12 answered again after a round of refinement: {refined}")
    check_done(refined, tmp, -12, 180)
    check(open(os.path.join(tmp, "deep.exr"), "rb").read() != before, "the refined map differs from the first")
    code, rest = srv.finish()
    check(code == 0 and rest == [], f"one round only, then the end: exit {code}, replies {rest}")
    resumed, _, _ = one_map(tmp, folder, "resumed", -12)
    check(resumed.get("cache") == "disk" and resumed.get("refined") == 1,
          f"a new server takes the refined band from the file ({resumed.get('cache')}, {resumed.get('refined')})")
    check_same_pixels(os.path.join(tmp, "resumed.exr"), os.path.join(tmp, "deep.exr"),
                      "the map from the refined file is the refined map")


with tempfile.TemporaryDirectory() as root:
    xdg = os.path.join(root, "xdg")
    folder = os.path.join(xdg, "firmament")  # the default cache folder, made with its parent
    built = None
    for part in PARTS:
        start = time.monotonic()
        os.mkdir(os.path.join(root, part))
        if part == "session":
            built = session(os.path.join(root, part), xdg)
        elif part == "signal":
            signals(os.path.join(root, part))
        elif part == "cache":
            cache(os.path.join(root, part), folder, built)
        elif part == "refine":
            refine(os.path.join(root, part))
        print(f"{part}: {time.monotonic() - start:.1f} s")
print(f"{len(failures)} failures" if failures else "all serve checks passed")
sys.exit(1 if failures else 0)

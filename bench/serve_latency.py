#!/usr/bin/env python3
"""`firmament serve` as the add-on's live sky uses it: the time from writing a request to reading its
reply (a map written and renamed into place, its sidecar read back), per atmosphere source.
Prints, for one atmosphere (the default sky, or the biome given):
  build   the first request (a sun of 30 degrees) of a server with an empty cache: the atmosphere
          built but for its twilight band (the suns below the horizon), then the map
  deep    that server's second request, a sun of -18 degrees: the twilight band built (and the
          cache file saved again), then the map
  disk    the first request of a second server on that cache: the atmosphere read from the disk
  memory  median, 90th percentile and largest of N sun changes (a sweep of elevations and azimuths)
          on a warm server not refining (--refine 0), one request at a time (each sent once the
          previous is answered)
  refining the same sweep on a server that refines its deep twilight tables while idle: each
          request sent 0.5 s after the previous reply, into a round of refinement under way, which
          it cancels
and where the time goes: the medians of the server's own "stage_seconds" (finding or building the
atmosphere, rendering the map, writing and renaming the files), and of the time outside the
server's own "seconds" (the pipe, parsing, reading the sidecar back, and while refining, the wait
for the round to stop).
Usage: bench/serve_latency.py build/firmament [--width W] [--quality Q] [--requests N] [--biome B]"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def request(proc, req):
    """Sends req (its id the next number) and returns (seconds until its reply, the reply); replies
    to earlier requests (a refined map: `refined`) are skipped."""
    request.id = getattr(request, "id", 0) + 1
    start = time.monotonic()
    proc.stdin.write(json.dumps({**req, "id": request.id}) + "\n")
    proc.stdin.flush()
    while (reply := json.loads(proc.stdout.readline())).get("id") != request.id:
        pass
    if reply.get("status") != "done":
        sys.exit(f"serve: {reply}")
    return time.monotonic() - start, reply


def server(fm, cache, cwd, *options):
    return subprocess.Popen([fm, "serve", "--cache", cache, *options], cwd=cwd, stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("firmament")
    ap.add_argument("--width", type=int, default=512)
    ap.add_argument("--quality", default="preview")
    ap.add_argument("--requests", type=int, default=40)
    ap.add_argument("--biome", default=None)
    a = ap.parse_args()
    fm = os.path.abspath(a.firmament)
    base = {"width": a.width, "quality": a.quality, **({"biome": a.biome} if a.biome else {})}
    with tempfile.TemporaryDirectory() as tmp:
        cache = os.path.join(tmp, "cache")
        rows = []
        for source in ("build", "disk"):
            p = server(fm, cache, tmp)
            t, reply = request(p, {**base, "output": "first.exr", "sun_elevation": 30})
            rows.append((source, reply["cache"], [t], [{**reply["stage_seconds"], "seconds": reply["seconds"]}]))
            if source == "build":
                t, reply = request(p, {**base, "output": "deep.exr", "sun_elevation": -18})
                rows.append(("deep", reply["cache"], [t], [{**reply["stage_seconds"], "seconds": reply["seconds"]}]))
            p.stdin.close()
            p.wait()
        for source, options, pause_s in (("memory", ("--refine", "0"), 0.0), ("refining", (), 0.5)):
            p = server(fm, cache, tmp, *options)
            request(p, {**base, "output": "warm.exr", "sun_elevation": -18})  # the band in memory
            client, own = [], []
            for i in range(a.requests):
                time.sleep(pause_s)  # idle: a round of refinement starts
                elevation = -18 + 108 * i / max(1, a.requests - 1)
                t, reply = request(p, {**base, "output": "live.exr", "sun_elevation": round(elevation, 3),
                                       "sun_azimuth": (37 * i) % 360})
                client.append(t)
                own.append({**reply["stage_seconds"], "seconds": reply["seconds"]})
            p.stdin.close()
            p.wait()
            rows.append((source, "memory", client, own))
    print(f"firmament serve, {a.width} x {a.width // 2} {a.quality} maps, {a.biome or 'default'} atmosphere")
    stages = ("atmosphere", "render", "write")
    print(f"{'source':8} {'reply':7} {'n':>3} {'median ms':>10} {'p90 ms':>8} {'max ms':>8}  "
          + " ".join(f"{s + ' ms':>13}" for s in stages) + f" {'outside ms':>11}")
    for source, said, client, own in rows:
        c = sorted(client)
        p90 = c[min(len(c) - 1, int(0.9 * len(c)))]
        outside = statistics.median(t - o["seconds"] for t, o in zip(client, own))
        print(f"{source:8} {said:7} {len(c):3} {1e3 * statistics.median(c):10.1f} {1e3 * p90:8.1f} "
              f"{1e3 * c[-1]:8.1f}  " + " ".join(f"{1e3 * statistics.median(o[s] for o in own):13.1f}" for s in stages)
              + f" {1e3 * outside:11.1f}")


main()

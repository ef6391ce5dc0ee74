#!/usr/bin/env python3
"""How long a render takes to stop after SIGINT, per stage: prints one line per (sky, stage) with the
seconds from the signal to the process's exit.  Each render is interrupted a delay after the stage's
first progress line.
Usage: bench/cancel_latency.py build/firmament [--delay S] [--sky day|night|twilight] [render options...]"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time

SKIES = {
    "day": ["--sun-elevation", "30"],
    "night": ["--sun-elevation", "-20"],
    "twilight": ["--sun-elevation", "-10"],
}


def interrupt_in(fm, sky, stage, delay, extra, out):
    args = [fm, "render", "--width", "256", "--quality", "final", "--progress", "json", "-o",
            os.path.join(out, "s.exr")] + SKIES[sky] + extra
    p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    seen = threading.Event()

    def read():
        for line in p.stdout:
            try:
                if json.loads(line).get("stage") == stage:
                    seen.set()
            except ValueError:
                pass

    reader = threading.Thread(target=read)
    reader.start()
    while not seen.is_set() and p.poll() is None:
        time.sleep(0.005)
    if not seen.is_set():
        reader.join()
        return None
    time.sleep(delay)
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    rc = p.wait()
    elapsed = time.monotonic() - t0
    reader.join()
    return elapsed, rc


def main():
    fm = sys.argv[1]
    rest = sys.argv[2:]
    delay = 0.3
    if rest[:1] == ["--delay"]:
        delay = float(rest[1])
        rest = rest[2:]
    skies = list(SKIES)
    if rest[:1] == ["--sky"]:
        skies = [rest[1]]
        rest = rest[2:]
    with tempfile.TemporaryDirectory() as out:
        for sky in skies:
            for stage in ["twilight guide", "ground irradiance", "multiple scattering", "single scattering", "pixels"]:
                r = interrupt_in(fm, sky, stage, delay, rest, out)
                if r is None:
                    print(f"{sky:9s} {stage:20s} (stage not reported)")
                else:
                    print(f"{sky:9s} {stage:20s} {r[0]:6.3f} s  exit {r[1]}")
                sys.stdout.flush()


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Random option sets for `firmament render` (the options and their ranges from `firmament options
--json`): extreme numbers, long strings, control characters, values at and beyond the ranges.  Each
case runs in an empty directory; checked: the exit status is 0, 1, 2 or 128 + a signal; exit 2
prints exactly one stderr line; a failed run leaves no file at all (temporaries included); no
sanitizer report.  A failing case is printed as a command line to replay.
Usage: fuzz_cli.py path/to/firmament [CASES] [SEED]"""
import json
import os
import random
import shlex
import subprocess
import sys
import tempfile

# every render is small: these are set for each case and never fuzzed (a 10^6-pixel-wide map is a
# valid request that would only take time)
FIXED = ["--width", "8", "--quality", "preview", "--progress", "none", "--threads", "1"]
NOT_FUZZED = {"--width", "--quality", "--samples", "--sample-scale", "--threads", "--help", "--progress",
              "--list-colorspaces", "--aspect"}
SANITIZER = ("AddressSanitizer", "LeakSanitizer", "runtime error:", "UndefinedBehaviorSanitizer")
# a hang detector: the slowest case (a stratocumulus deck at width 8 with a cold cloud cache) takes
# about 18 s under the sanitizers alone, and a CI machine may run other tests beside it
TIMEOUT_S = 180
# cases run before the random ones: a night sun (-25 to -50 degrees) that the seed may draw, where
# twilight's heavy paths once split without end (transport/twilight.c)
PINNED = [["--sun-elevation", "-31.5"]]


def extreme_number(r):
    return r.choice(["0", "-0", "1e308", "-1e308", "1e-320", "nan", "inf", "-inf", "1e", "0x10", " 5",
                     "99999999999999999999", "-1", "1.7976931348623157e308", "4.9e-324", "+3", "1,5", ""])


def weird_string(r):
    n = r.choice([1, 255, 256, 1100, 5000])
    kind = r.randrange(4)
    if kind == 0:
        return "a" * n
    if kind == 1:
        return "".join(chr(r.randrange(1, 32)) for _ in range(r.randrange(1, 20)))
    if kind == 2:
        return "x\ny\rz\x1b[31m\t" + "é" * r.randrange(3)
    return "/" * r.randrange(1, 4) + "nonexistent/" * r.randrange(3) + "f.json"


def value_for(opt, r):
    kind = opt["kind"]
    if r.random() < 0.35:
        return extreme_number(r) if r.random() < 0.6 else weird_string(r)
    if kind == "number" or kind == "whole":
        lo, hi = opt.get("min"), opt.get("max")
        if lo is None or hi is None:
            return str(r.uniform(-1e3, 1e3))
        pick = r.randrange(4)
        if pick == 0:
            return repr(lo)
        if pick == 1:
            return repr(hi)
        v = r.uniform(lo, hi) if pick == 2 else r.uniform(lo - (hi - lo), hi + (hi - lo))
        return str(int(v)) if kind == "whole" else repr(v)
    if kind == "choice" or opt.get("choices"):
        return r.choice(opt["choices"] + ["", "x"])
    if kind == "time":
        return r.choice(["12:00", "23:59:59", "24:00", "00:00", "12:60", "1:2", "-1:00"])
    if kind == "date":
        return r.choice(["2024-06-21", "1900-01-01", "2100-12-31", "2023-02-29", "0000-00-00"])
    if kind == "utc_offset":
        return r.choice(["+00:00", "+14:00", "-12:00", "+14:01", "+1", "Z"])
    if opt["flag"] in ("--output", "--sidecar", "--sun-disk-map", "--spectral"):
        return r.choice(["s.exr", "s.hdr", "d.exr", "x.json", "sub/s.exr", ".", "s"])
    if opt["flag"] == "--preview":
        return r.choice(["p.png", "s.exr", "p"])
    return weird_string(r)


def make_case(options, r):
    args = ["render"] + FIXED
    for opt in r.sample(options, r.randrange(1, 5)):
        if opt["kind"] == "switch":
            args.append(opt["flag"])
        else:
            args += [opt["flag"], value_for(opt, r)]
    return args


def check(fm, args, work):
    """The problems of one case (empty when all is well)."""
    try:
        p = subprocess.run([fm] + args, cwd=work, capture_output=True, timeout=TIMEOUT_S)
        rc, err = p.returncode, p.stderr.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        return [f"no exit within {TIMEOUT_S} s"]
    problems = []
    if rc < 0:
        problems.append(f"killed by signal {-rc}")
    elif rc not in (0, 1, 2) and not 129 <= rc <= 128 + 64:
        problems.append(f"exit {rc}")
    if any(s in err for s in SANITIZER):
        problems.append("sanitizer report: " + err[:2000])
    if rc == 2 and (err.count("\n") != 1 or not err.startswith("firmament: ")):
        problems.append(f"exit 2 with {err.count(chr(10))} stderr lines: {err[:500]!r}")
    left = os.listdir(work)
    if rc != 0 and left:
        problems.append(f"exit {rc} left files: {left[:5]}")
    return problems


def main():
    fm = os.path.abspath(sys.argv[1])
    cases = int(sys.argv[2]) if len(sys.argv) > 2 else 300
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 50
    options = [o for o in json.loads(subprocess.run([fm, "options", "--json"], capture_output=True,
                                                    check=True).stdout)["options"]
               if o["flag"] not in NOT_FUZZED]
    r = random.Random(seed)
    failures = 0
    exits = {}
    pinned = [["render"] + FIXED + extra for extra in PINNED]
    for i in range(len(pinned) + cases):
        args = pinned[i] if i < len(pinned) else make_case(options, r)
        with tempfile.TemporaryDirectory() as work:
            os.mkdir(os.path.join(work, "run"))
            run = os.path.join(work, "run")
            problems = check(fm, args, run)
        key = "ok" if not problems else "bad"
        exits[key] = exits.get(key, 0) + 1
        if problems:
            failures += 1
            print(f"FAIL case {i}: {'; '.join(problems)}\n  firmament {shlex.join(args)}")
    print(f"{len(pinned)} pinned + {cases} cases (seed {seed}): {exits.get('ok', 0)} passed, {failures} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

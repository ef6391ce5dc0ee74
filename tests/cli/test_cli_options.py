#!/usr/bin/env python3
"""`firmament options --json` against what the executable enforces.

Usage: test_cli_options.py FIRMAMENT [docs/cli.md [--write-table]]

For every option with a numeric range in the JSON, the command line and a sky preset (when the
option has a preset key) accept the range's ends (or just inside an open end) and refuse just
outside with exit status 2 and one line naming the option; every choice word is accepted and an
unknown one refused; every option appears in `--help`; the table of options in docs/cli.md (between
its "options table" markers) is the one made from the JSON (--write-table rewrites it), and its
text holds no illuminance figure copied by hand.  Values are
checked by parsing only: `--list-colorspaces` exits after the options are read, before any render.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

FIRMAMENT = os.path.abspath(sys.argv[1])
TABLE_DOC = sys.argv[2] if len(sys.argv) > 2 else None  # the Markdown file holding the options table
WRITE_TABLE = "--write-table" in sys.argv[3:]
BEGIN = "<!-- options table: made by tests/cli/test_cli_options.py from `firmament options --json` -->"
END = "<!-- end of the options table -->"

# What an option needs beside it to be valid at all (the rules between options, not the ranges).
TIME = ["--date", "2024-06-21", "--time", "12:00", "--latitude", "45", "--longitude", "7"]
CONTEXT = {
    "--latitude": ["--date", "2024-06-21"],
    "--longitude": ["--date", "2024-06-21", "--latitude", "45"],
    "--pressure": TIME,
    "--temperature": TIME,
    "--delta-t": TIME,
    "--refraction": TIME,
    "--utc-offset": TIME,
    "--step": ["--date", "2024-06-21", "--latitude", "45", "--longitude", "7", "--time-start", "12:00",
               "--time-end", "12:00"],
    "--fov": ["--camera", "pinhole"],
    "--look-azimuth": ["--camera", "pinhole"],
    "--look-elevation": ["--camera", "pinhole"],
    "--fisheye-projection": ["--camera", "fisheye"],
    "--samples": ["--quality", "reference"],
    "--exposure": ["--preview", "p.png"],
}
PRESET_CONTEXT = {
    "latitude": {"date": "2024-06-21"},
    "longitude": {"date": "2024-06-21", "latitude": 45},
    "fov": {"camera": "pinhole"},
    "look_azimuth": {"camera": "pinhole"},
    "look_elevation": {"camera": "pinhole"},
}

checks = failures = 0


def check(ok, what):
    global checks, failures
    checks += 1
    if not ok:
        failures += 1
        print("FAIL:", what)


def run(args, cwd):
    p = subprocess.run([FIRMAMENT] + args, cwd=cwd, capture_output=True, text=True, timeout=60)
    return p.returncode, p.stderr


def number(x, whole):
    return str(int(x)) if whole else repr(float(x))


def values(o):
    """(accepted, refused) values at the range's ends."""
    lo, hi, whole = o["min"], o["max"], o["kind"] == "whole"
    step = 1 if whole else max(abs(hi - lo), 1.0) * 1e-6
    inside_lo = lo + step if o["min_open"] else lo
    return [inside_lo, hi], [lo if o["min_open"] else lo - step, hi + step]


def expect_refused(args, flag, what, cwd):
    code, err = run(args, cwd)
    lines = err.strip().splitlines()
    check(code == 2 and len(lines) == 1 and flag in lines[0],
          f"{what}: exit {code}, stderr {err.strip()!r} (want 2 and one line naming {flag})")


def cell(text):
    return text.replace("|", "\\|")


def markdown_table(options):
    """The Markdown table of options, by group."""
    rows = ["| option | meaning | default |", "|---|---|---|"]
    group = None
    for o in options:
        if o["group"] != group:
            group = o["group"]
            rows.append(f"| **{cell(group.split(' (')[0])}** | | |")
        flag = (o["short"] + ", " if "short" in o else "") + o["flag"] + (" " + o["metavar"] if "metavar" in o else "")
        rows.append(f"| `{cell(flag)}` | {cell(o['help'])} | {cell(o.get('default_text', ''))} |")
    return "\n".join(rows) + "\n"


def check_table_doc(options):
    text = open(TABLE_DOC).read()
    if BEGIN not in text or END not in text:
        check(False, f"{TABLE_DOC} has no options table markers ({BEGIN})")
        return
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    table = markdown_table(options)
    # what a render measures is not copied into the text by hand (it would go stale): no illuminance
    hand = re.findall(r"\b\d[\d.,]*\s*k?lx\b", head + tail)
    check(not hand, f"{TABLE_DOC} holds illuminance figures written by hand: {hand} (a render's sidecar has them)")
    if WRITE_TABLE:
        open(TABLE_DOC, "w").write(head + BEGIN + "\n" + table + END + tail)
    else:
        check(rest.split(END, 1)[0].strip() == table.strip(),
              f"the options table of {TABLE_DOC} differs from `firmament options --json` "
              f"(tests/cli/test_cli_options.py FIRMAMENT {TABLE_DOC} --write-table rewrites it)")


def check_no_biomes(work):
    """A presets folder without biomes: --biome offers only "none" and one line on stderr names the folder."""
    empty = os.path.join(work, "no-biomes")
    os.makedirs(os.path.join(empty, "biomes"), exist_ok=True)
    # the clouds are there (they warn alike when missing): only the biomes are
    shutil.copytree(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "presets", "clouds"),
                    os.path.join(empty, "clouds"), dirs_exist_ok=True)
    r = subprocess.run([FIRMAMENT, "options", "--json"], capture_output=True, text=True,
                       env=dict(os.environ, FIRMAMENT_PRESETS=empty))
    check(r.returncode == 0, f"options --json without biomes: exit {r.returncode}: {r.stderr.strip()}")
    try:
        biome = next(o for o in json.loads(r.stdout)["options"] if o["flag"] == "--biome")
        check(biome["choices"] == ["none"], f"--biome choices without biomes: {biome['choices']}")
    except (ValueError, KeyError, StopIteration) as e:
        check(False, f"options --json without biomes: {e}")
    lines = r.stderr.strip().splitlines()
    check(len(lines) == 1 and empty in lines[0], f"options --json without biomes, stderr: {r.stderr!r}")
    # the usage and the JSON with their warning on one stream: the warning once, before them, never inside
    for cmd in (["--help"], ["options", "--json"]):
        r = subprocess.run([FIRMAMENT] + cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           env=dict(os.environ, FIRMAMENT_PRESETS=empty))
        lines = r.stdout.splitlines()
        warned = [i for i, line in enumerate(lines) if "warning" in line]
        check(r.returncode == 0 and warned == [0] and "no biomes" in lines[0],
              f"{' '.join(cmd)} without biomes, stdout and stderr together: the warning first and once "
              f"(lines {warned} of {len(lines)}, exit {r.returncode})")


def main():
    out = subprocess.run([FIRMAMENT, "options", "--json"], capture_output=True, text=True, check=True).stdout
    try:
        table = json.loads(out)
    except ValueError as e:
        print("FAIL: options --json is not JSON:", e)
        return 1
    options = table["options"]
    check(len(options) > 40, f"{len(options)} options")
    usage = subprocess.run([FIRMAMENT, "--help"], capture_output=True, text=True, check=True).stdout
    if TABLE_DOC:
        check_table_doc(options)
    with tempfile.TemporaryDirectory() as work:
        for o in options:
            flag = o["flag"]
            check(flag + " " in usage or flag + "\n" in usage, f"{flag} is not in --help")
            ctx = CONTEXT.get(flag, [])
            if "min" in o:
                whole = o["kind"] == "whole"
                good, bad = values(o)
                for v in good:
                    code, err = run(["render"] + ctx + [flag, number(v, whole), "--list-colorspaces"], work)
                    check(code == 0, f"{flag} {number(v, whole)} (in {o['min']}..{o['max']}) refused: {err.strip()}")
                for v in bad:
                    expect_refused(["render"] + ctx + [flag, number(v, whole), "--list-colorspaces"], flag,
                                   f"{flag} {number(v, whole)}", work)
                key = o["preset_key"]
                if key:
                    for v, ok in [(x, True) for x in good] + [(x, False) for x in bad]:
                        preset = dict(PRESET_CONTEXT.get(key, {}), name="range", **{key: v})
                        path = os.path.join(work, "p.json")
                        with open(path, "w") as f:
                            json.dump(preset, f)
                        args = ["render", "--preset", path, "--list-colorspaces"]
                        if ok:
                            code, err = run(args, work)
                            check(code == 0, f"preset {key}: {v} refused: {err.strip()}")
                        else:
                            expect_refused(args, "$." + key, f"preset {key}: {v}", work)
            if o["kind"] == "choice":
                for word in o["choices"]:
                    code, err = run(["render"] + ctx + [flag, word, "--list-colorspaces"], work)
                    check(code == 0, f"{flag} {word} refused: {err.strip()}")
                expect_refused(["render"] + ctx + [flag, "no-such-word", "--list-colorspaces"], flag, f"{flag} no-such-word", work)
        biome = next(o for o in options if o["flag"] == "--biome")
        on_disk = sorted(f[:-5] for f in os.listdir(os.path.join(os.path.dirname(__file__), "../../presets/biomes"))
                         if f.endswith(".json"))
        check(biome["choices"] == ["none"] + on_disk, f"--biome choices {biome['choices']} vs presets/biomes {on_disk}")
        check_no_biomes(work)
        quality = next(o for o in options if o["flag"] == "--quality")
        check(quality["choices"] == ["preview", "final", "reference"], f"--quality choices {quality['choices']}")
    print(f"{checks - failures} checks passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

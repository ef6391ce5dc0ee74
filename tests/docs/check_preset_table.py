#!/usr/bin/env python3
"""docs/cli.md's table "The shipped presets" says what the program does with each preset: one row per
file of presets/skies/ and one file per row, and each row's date, time, offset, altitude, sun, biome,
turbidity or AOD, humidity, ozone, cloud and albedo as the sidecar of the preset's render reports them
(a map of 16 x 8 pixels at 550 nm, enough for the sidecar). Also the README's list of the presets
names every file once, those with clouds after "with clouds". Not checked: the places' names and the
sun's notes after its direction ("hidden", "dim").
Usage: check_preset_table.py FIRMAMENT [ROOT]"""
import concurrent.futures
import glob
import json
import os
import re
import subprocess
import sys
import tempfile

FIRMAMENT = os.path.abspath(sys.argv[1])
ROOT = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "../.."))
ANGLE_TOL_DEG = 0.05  # the table prints angles to 0.1 degree
KOSCHMIEDER = 3.912  # -ln(0.02), as core/src/api.c: fog visibility = 3.912 / extinction
# 16-point compass: a direction names the point within 11.25 degrees of the azimuth
POINTS = ["N", "NNE", "NE", "ENE", "E", "ESE", "SE", "SSE", "S", "SSW", "SW", "WSW", "W", "WNW", "NW", "NNW"]
WORDS = {"n": "north", "e": "east", "s": "south", "w": "west"}


def point_of(word):
    """'south-east' or 'SE' -> 'SE'; None for a word that is no compass point."""
    parts = word.lower().split("-")
    if len(parts) == 1 and word.upper() in POINTS:
        return word.upper()
    inv = {v: k for k, v in WORDS.items()}
    if all(p in inv for p in parts):
        p = "".join(inv[x] for x in parts).upper()
        return p if p in POINTS else None
    return None


def compass(azimuth_deg):
    return POINTS[int(((azimuth_deg % 360) + 11.25) // 22.5) % 16]


def sidecar(name, tmp):
    """The sidecar of the preset's smallest render (the sun and atmosphere do not depend on the size,
    the wavelength or the samples)."""
    out = os.path.join(tmp, name + ".exr")
    env = dict(os.environ, FIRMAMENT_PRESETS=os.path.join(ROOT, "presets"))
    subprocess.run([FIRMAMENT, "render", "--preset", name, "--quality", "preview", "--width", "16",
                    "--wavelength", "550", "--sample-scale", "0.001", "--threads", "1", "--progress", "none",
                    "-o", out], check=True, env=env, stdout=subprocess.DEVNULL)
    with open(os.path.join(tmp, name + ".json"), encoding="utf-8") as f:
        return json.load(f)


def default_humidity(biome):
    out = subprocess.run([FIRMAMENT, "render", "--biome", biome, "--print-atmosphere"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["humidity_percent"]


def table_rows(text):
    """{preset: [cells]} of the table after 'The shipped presets', and the names seen twice."""
    lines = text[text.index("The shipped presets"):].splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("|"))
    rows, twice = {}, []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        m = re.match(r'`([\w-]+)` "([^"]+)"$', cells[0])
        name = m.group(1) if m else cells[0]
        if name in rows:
            twice.append(name)
        rows[name] = [m.group(2) if m else None] + cells[1:]
    return rows, twice


def near(a, b, tol=1e-9):
    return abs(float(a) - float(b)) <= tol * max(1.0, abs(float(b)))


def same(x, y):
    """Numbers within near(), anything else (None, "climatology") equal."""
    numbers = all(isinstance(v, (int, float)) for v in (x, y))
    return near(x, y) if numbers else x == y


def check_place(cell, p):
    if cell == "(no place)":
        return [] if "time" not in p else [f"'{cell}' but the sun comes from {p['date']} {p['time']}"]
    m = re.match(r"[^,]+, (\d{4}-\d\d-\d\d) (\d\d:\d\d) \(([+-]\d\d:\d\d)\)(?:, (\d+) m)?$", cell)
    if not m:
        return [f"place '{cell}' is not 'PLACE, YYYY-MM-DD HH:MM (+HH:MM)[, N m]'"]
    date, time, offset, alt = m.groups()
    got = (p.get("date"), p.get("time", "")[:5], p.get("utc_offset"), p["observer_altitude_m"])
    want = (date, time, offset, float(alt or 0))
    return [] if got == want else [f"place '{cell}': the program has {got}"]


def check_sun(cell, s):
    el, az = s["elevation_deg"], s["azimuth_deg"]
    parts = cell.split(", ")
    m = re.match(r"(\d+(?:\.\d+)?)° (up|below the horizon)$", parts[0])
    if not m:
        return [f"sun '{cell}' does not start 'E° up' or 'E° below the horizon'"]
    said = float(m.group(1)) * (1 if m.group(2) == "up" else -1)
    bad = [] if abs(said - el) <= ANGLE_TOL_DEG else [f"sun '{parts[0]}': elevation {el:.2f}°"]
    m = re.match(r"([A-Za-z-]+)(?: \((\d+(?:\.\d+)?)°\))?$", parts[1]) if len(parts) > 1 else None
    point = point_of(m.group(1)) if m else None
    if point is None:
        return bad + [f"sun '{cell}': no compass direction after the elevation (azimuth {az:.2f}°)"]
    if point != compass(az):
        bad.append(f"sun '{parts[1]}': azimuth {az:.2f}° is {compass(az)} (16 points)")
    if m.group(2) and abs(float(m.group(2)) - az) > ANGLE_TOL_DEG:
        bad.append(f"sun '{parts[1]}': azimuth {az:.2f}°")
    return bad


def check_cloud(cell, a):
    if a.get("cloud_layers", 0) != (1 if cell else 0):
        return [f"clouds '{cell}': the program has {a.get('cloud_layers', 0)} layers"]
    if not cell:
        return []
    parts, bad = cell.split(", "), []
    m = re.match(r"(\w+) at (\d+(?:\.\d+)?) km$", parts[0]) or re.match(r"(fog) (\d+) m deep$", parts[0])
    if not m:
        return [f"cloud '{parts[0]}' is not 'TYPE at N km' or 'fog N m deep'"]
    if m.group(1) != a["cloud_1_type"]:
        bad.append(f"cloud '{parts[0]}': the program has {a['cloud_1_type']}")
    elif m.group(1) == "fog" and not near(float(m.group(2)) / 1000, a["cloud_1_thickness_km"]):
        bad.append(f"cloud '{parts[0]}': {a['cloud_1_thickness_km']} km deep")
    elif m.group(1) != "fog" and not near(m.group(2), a["cloud_1_base_km"]):
        bad.append(f"cloud '{parts[0]}': base {a['cloud_1_base_km']} km")
    tau = a["cloud_1_optical_depth_550nm"]
    for part in parts[1:]:
        t = re.match(r"tau (\d+(?:\.\d+)?)$", part)
        v = re.match(r"visibility (\d+) m$", part)
        if t and not near(t.group(1), tau):
            bad.append(f"cloud '{part}': tau {tau}")
        elif v and not near(v.group(1), KOSCHMIEDER * a["cloud_1_thickness_km"] / tau * 1000, 1e-3):
            bad.append(f"cloud '{part}': tau {tau} in {a['cloud_1_thickness_km']} km")
        elif not t and not v:
            bad.append(f"cloud '{part}' is not 'tau N' or 'visibility N m'")
    return bad


def check_aerosol(cell, p, a):
    aerosol, _, cloud = cell.partition("; ")
    parts = aerosol.split(", ")
    biome = parts[0].replace(" ", "-")
    bad = [] if biome == p["biome"] else [f"biome '{parts[0]}': the program has {p['biome']}"]
    said = {"turbidity": 1.0, "aod550": None, "humidity": default_humidity(p["biome"]), "ozone": "climatology"}
    for part in parts[1:]:
        for key, pattern in (("turbidity", r"turbidity (\d+(?:\.\d+)?)$"), ("aod550", r"AOD (\d+(?:\.\d+)?)$"),
                             ("humidity", r"(\d+)%(?: humidity)?$"), ("ozone", r"(\d+) DU$")):
            m = re.match(pattern, part)
            if m:
                said[key] = float(m.group(1))
                break
        else:
            bad.append(f"aerosol '{part}' is not 'turbidity N', 'AOD N', 'N% humidity' or 'N DU'")
    got = {"turbidity": p["turbidity"], "aod550": p.get("aod550"), "humidity": a["humidity_percent"],
           "ozone": p["ozone_column_du"]}
    for key in said:
        if not same(said[key], got[key]):
            bad.append(f"aerosol '{aerosol}': {key} is {got[key]}, the row says {said[key]}")
    return bad + check_cloud(cloud, a)


def check_row(cells, preset, car):
    display, place, sun, aerosol, albedo = cells
    p, a = car["parameters"], car["atmosphere"]
    bad = [] if display == preset["name"] else [f"name '{display}': the file says '{preset['name']}'"]
    bad += check_place(place, p) + check_sun(sun, car["sun"]) + check_aerosol(aerosol, p, a)
    m = re.match(r"(\d+(?:\.\d+)?)(?: \(.*\))?$", albedo)
    if not m or not near(m.group(1), p["ground_albedo"]):
        bad.append(f"albedo '{albedo}': the program has {p['ground_albedo']}")
    return bad


def check_readme(names, clouded):
    text = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
    m = re.search(r"The shipped ones \(`presets/skies/`[^)]*\):(.*?)\. Their", text, re.S)
    if not m:
        return ["README: no list 'The shipped ones (`presets/skies/`, ...): ...'"]
    clear, _, cloudy = m.group(1).partition("with clouds")
    listed = re.findall(r"`([\w-]+)`", clear), re.findall(r"`([\w-]+)`", cloudy)
    want = sorted(n for n in names if n not in clouded), sorted(clouded)
    if sorted(listed[0]) == want[0] and sorted(listed[1]) == want[1]:
        return []
    return [f"README lists {listed[0]} and with clouds {listed[1]}; presets/skies/ has {want[0]} and {want[1]}"]


def main():
    names = sorted(os.path.basename(f)[:-5] for f in glob.glob(os.path.join(ROOT, "presets", "skies", "*.json")))
    rows, twice = table_rows(open(os.path.join(ROOT, "docs", "cli.md"), encoding="utf-8").read())
    bad = [f"{n}: two rows" for n in twice]
    bad += [f"{n}: no row in docs/cli.md" for n in names if n not in rows]
    bad += [f"{n}: a row but no presets/skies/{n}.json" for n in rows if n not in names]
    with tempfile.TemporaryDirectory() as tmp, concurrent.futures.ThreadPoolExecutor(os.cpu_count()) as pool:
        cars = dict(zip(names, pool.map(lambda n: sidecar(n, tmp), names)))
    for n in names:
        if n in rows:
            preset = json.load(open(os.path.join(ROOT, "presets", "skies", n + ".json"), encoding="utf-8"))
            bad += [f"{n}: {b}" for b in check_row(rows[n], preset, cars[n])]
    bad += check_readme(names, [n for n in names if cars[n]["atmosphere"].get("cloud_layers", 0)])
    for n in names:
        s = cars[n]["sun"]
        print(f"{n}: sun {s['elevation_deg']:.2f}° up, azimuth {s['azimuth_deg']:.2f}° ({compass(s['azimuth_deg'])})")
    for b in bad:
        print("FAIL:", b)
    print(f"{len(names)} presets, {len(rows)} rows, {len(bad)} wrong")
    return 1 if bad or not names else 0


if __name__ == "__main__":
    sys.exit(main())

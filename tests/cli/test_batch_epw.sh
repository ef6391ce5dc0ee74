#!/usr/bin/env bash
# firmament batch plan --epw (docs/batch.md): the place from the LOCATION line, one job per hour with
# the sun up, the aerosol optical depth and albedo of valid fields, missing codes left out, the sky
# cover in the manifest and the sidecar; a malformed file refused naming its line and field.
# Usage: test_batch_epw.sh path/to/firmament
set -u
FM=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
EPW=$here/../data/epw/synthetic.epw
. "$here/harness.sh"
cd "$work"

"$FM" batch plan -o m.jsonl --epw "$EPW" --set width=16 --set quality=preview >/dev/null || fail "plan --epw failed"
# Independent expectations from the file itself and published sun times at 48.86 N 2.35 E (Paris,
# timeanddate.com): 2025-06-21 sunrise 05:47, sunset 21:58 CEST = 04:47 and 20:58 at the file's
# +1 h; 2025-12-21 sunrise 08:42, sunset 16:56 CET.  Hour N is the sky at N-1:30, so the hours
# 6-21 of June (05:30-20:30) and 10-17 of December (09:30-16:30) have the sun up: 16 + 8 jobs.
python3 - m.jsonl "$EPW" <<'PY' && ok || fail "the jobs do not follow the weather file"
import json, sys
jobs = [json.loads(l) for l in open(sys.argv[1])]
rows = {}
for line in open(sys.argv[2]).read().splitlines()[8:]:
    f = line.split(",")
    rows[(int(f[1]), int(f[2]), int(f[3]))] = f
june = [j for j in jobs if j["date"] == "2025-06-21"]
dec = [j for j in jobs if j["date"] == "2025-12-21"]
assert [j["time"] for j in june] == ["%02d:30:00" % h for h in range(5, 21)], [j["time"] for j in june]
assert [j["time"] for j in dec] == ["%02d:30:00" % h for h in range(9, 17)], [j["time"] for j in dec]
for j in jobs:
    assert (j["latitude"], j["longitude"], j["utc_offset"]) == (48.86, 2.35, "+01:00")
    m, d, hour = int(j["date"][5:7]), int(j["date"][8:]), int(j["time"][:2]) + 1
    f = rows[(m, d, hour)]
    cover, aod, albedo = f[22], f[29], f[32]
    # field 23: total sky cover in tenths, 99 missing
    assert j.get("sky_cover_tenths") == (None if cover == "99" else int(cover)), (j, cover)
    # field 30: broadband AOD (~ AOD at 700 nm), .999 missing; to 550 nm with Angstrom 1.3
    if aod == ".999":
        assert "aod550" not in j, j
    else:
        assert abs(j["aod550"] - float(aod) * (700 / 550) ** 1.3) < 2e-3 * j["aod550"], (j, aod)
    # field 33: albedo, 999 missing
    assert j.get("albedo") == (None if albedo == "999" else float(albedo)), (j, albedo)
    assert j["output"].startswith("maps/Testville_")
print("epw: %d jobs, %d with sky cover, %d with AOD, %d with albedo" % (len(jobs),
      sum("sky_cover_tenths" in j for j in jobs), sum("aod550" in j for j in jobs), sum("albedo" in j for j in jobs)))
PY
# the sky cover reaches the sidecar with the job; the AOD reaches the atmosphere
"$FM" batch run m.jsonl --index 2 >/dev/null || fail "batch run of an EPW job failed"
python3 - m.jsonl <<'PY' && ok || fail "the sidecar does not carry the sky cover or the AOD"
import json, sys
job = json.loads(open(sys.argv[1]).read().splitlines()[2])
side = json.load(open(job["sidecar"]))
assert side["job"]["sky_cover_tenths"] == job["sky_cover_tenths"] == 5
assert abs(side["atmosphere"]["aerosol_optical_depth_550nm"] - job["aod550"]) < 1e-3 * job["aod550"], side["atmosphere"]
PY

# --- batch summary: the sidecars as CSV rows and a heat map (day of year x hour) -------------------
"$FM" batch run m.jsonl --index 20 >/dev/null || fail "batch run of job 20 failed"
"$FM" batch summary m.jsonl >/dev/null || fail "batch summary failed"
python3 - m.jsonl m.csv m.png <<'PY' && ok || fail "batch summary's CSV or PNG"
import csv, datetime, json, struct, sys, zlib
jobs = [json.loads(l) for l in open(sys.argv[1])]
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == len(jobs) == 24
lux = {}
for i, (job, row) in enumerate(zip(jobs, rows)):
    assert row["date"] == job["date"] and row["time"] == job["time"]
    cover = job.get("sky_cover_tenths")
    if i in (2, 20):
        side = json.load(open(job["sidecar"]))
        for key, group in (("global_horizontal_illuminance_lux", "sky"), ("diffuse_horizontal_illuminance_lux", "sky"),
                           ("direct_horizontal_illuminance_lux", "sun"), ("sun_elevation_deg", None)):
            want = side["sun"]["elevation_deg"] if group is None else side[group][key]
            assert abs(float(row[key]) - want) <= 1e-5 * abs(want), (key, row[key], want)
        assert row["flags"] == ("cloudy" if cover is not None and cover >= 5 else ""), row
        d = datetime.date.fromisoformat(job["date"])
        lux[(d.timetuple().tm_yday, int(job["time"][:2]))] = float(row["global_horizontal_illuminance_lux"])
    else:
        assert row["flags"] == "missing" and row["global_horizontal_illuminance_lux"] == "", row
# PNG: 8-bit RGB, 2 x 8 pixels per day and hour; decoded here (the five PNG filters)
data = open(sys.argv[3], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n"
pos, idat, w, h = 8, b"", 0, 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b"IHDR":
        w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
        assert (depth, ctype) == (8, 2)
    elif kind == b"IDAT":
        idat += body
    pos += 12 + n
raw, stride, img, prev = zlib.decompress(idat), 3 * w, [], bytearray(3 * w)
for y in range(h):
    f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for x in range(stride):
        a = line[x - 3] if x >= 3 else 0
        b, c = prev[x], (prev[x - 3] if x >= 3 else 0)
        p = a + b - c
        pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else b if abs(p - b) <= abs(p - c) else c][f]
        line[x] = (line[x] + pred) & 255
    img.append(line)
    prev = line
assert (w, h) == (366 * 2, 24 * 8), (w, h)
pixel = lambda day, hour: tuple(img[(hour - 0) * 8 + 4][(day - 1) * 2 * 3:(day - 1) * 2 * 3 + 3])
brightest = max(lux, key=lux.get)
assert pixel(*brightest) == (253, 231, 37), pixel(*brightest)         # the top of the ramp
for cell in lux:
    assert pixel(*cell) != (0, 0, 0)
dark = [(d, hr) for d in (172, 355) for hr in range(24) if (d, hr) not in lux]
assert all(pixel(*c) == (0, 0, 0) for c in dark)                       # no map: black
PY

# --- malformed files: one line naming the line and the field, exit 2, nothing written -------------
broken() { # broken LINE FIELD VALUE: a copy of the file with that field of that line replaced
    awk -F, -v OFS=, -v l="$1" -v f="$2" -v v="$3" 'NR == l { $f = v } 1' "$EPW" >"$work/bad.epw"
}
broken 12 30 abc
expect_usage_error "a word for the AOD" batch plan -o m2.jsonl --epw "$work/bad.epw"
grep -q "bad.epw: line 12, field 30 (Aerosol Optical Depth): 'abc'" "$work/stderr" && ok || fail "AOD: $(cat "$work/stderr")"
broken 20 3 31
expect_usage_error "a day that does not exist" batch plan -o m2.jsonl --epw "$work/bad.epw"
grep -q 'line 20, field 3 (Day)' "$work/stderr" && ok || fail "day: $(cat "$work/stderr")"
awk -F, -v OFS=, 'NR == 30 { NF = 22 } 1' "$EPW" >"$work/bad.epw"
expect_usage_error "a short line" batch plan -o m2.jsonl --epw "$work/bad.epw"
grep -q 'line 30: 22 fields, an EPW data line has 35' "$work/stderr" && ok || fail "short: $(cat "$work/stderr")"
broken 1 7 north
expect_usage_error "a bad latitude" batch plan -o m2.jsonl --epw "$work/bad.epw"
grep -q 'line 1, field 7' "$work/stderr" && ok || fail "latitude: $(cat "$work/stderr")"
broken 40 23 12
expect_usage_error "sky cover beyond 10 tenths" batch plan -o m2.jsonl --epw "$work/bad.epw"
grep -q 'line 40, field 23 (Total Sky Cover)' "$work/stderr" && ok || fail "sky cover: $(cat "$work/stderr")"
broken 15 33 999.5
expect_usage_error "an albedo that is no missing code" batch plan -o m2.jsonl --epw "$work/bad.epw"
grep -q 'line 15, field 33 (Albedo)' "$work/stderr" && ok || fail "albedo: $(cat "$work/stderr")"

echo "test_batch_epw: $checks checks, $failures failures"
[ "$failures" -eq 0 ]

#!/usr/bin/env python3
"""--format hdr: a Radiance RGBE picture with a correct header, read back by OpenImageIO (oiiotool,
where installed) or by a decoder written here from the format's description; a white Lambertian
card's illuminance computed from the picture with Radiance's convention (179 lm/W, values x 683/179)
matches the sidecar's within 1%.  Usage: test_radiance.py path/to/firmament"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

FM = os.path.abspath(sys.argv[1])
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def header_and_pixels(path):
    data = open(path, "rb").read()
    end = data.index(b"\n\n")
    header = data[:end].decode().split("\n")
    rest = data[end + 2:]
    res_end = rest.index(b"\n")
    res = rest[:res_end].decode().split()
    assert res[0] == "-Y" and res[2] == "+X", res
    h, w = int(res[1]), int(res[3])
    body = rest[res_end + 1:]
    assert len(body) == 4 * w * h, (len(body), w, h)  # flat (not run-length encoded) scanlines
    px = []
    for i in range(w * h):
        r, g, b, e = body[4 * i:4 * i + 4]
        f = math.ldexp(1.0, e - 136) if e else 0.0  # 2^(e-128) / 256
        px.append((r * f, g * f, b * f))
    return header, w, h, px


def oiio_pixels(path, w, h):
    out = subprocess.run(["oiiotool", "--dumpdata", path], check=True, capture_output=True, text=True).stdout
    px = [None] * (w * h)
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("Pixel ("):
            xy, vals = line[7:].split("):")
            x, y = (int(t) for t in xy.split(","))
            px[y * w + x] = tuple(float(v) for v in vals.split())
    assert None not in px
    return px


def luminance_row(primaries):
    """Y of R, G, B = 1 from the chromaticities (SMPTE RP 177): the second row of RGB -> XYZ."""
    rx, ry, gx, gy, bx, by, wx, wy = primaries
    cols = [(x / y, 1.0, (1 - x - y) / y) for x, y in ((rx, ry), (gx, gy), (bx, by))]
    W = (wx / wy, 1.0, (1 - wx - wy) / wy)
    m = [[cols[j][i] for j in range(3)] for i in range(3)]
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
           + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    def solve(col):  # Cramer's rule: S = M^-1 W
        mm = [row[:] for row in m]
        for i in range(3):
            mm[i][col] = W[i]
        return (mm[0][0] * (mm[1][1] * mm[2][2] - mm[1][2] * mm[2][1]) - mm[0][1] * (mm[1][0] * mm[2][2] - mm[1][2] * mm[2][0])
                + mm[0][2] * (mm[1][0] * mm[2][1] - mm[1][1] * mm[2][0])) / det
    return [solve(j) for j in range(3)]  # Y row: cols[j][1] = 1 times S_j


def card_lux(px, w, h, yrow):
    """Illuminance on a horizontal white Lambertian card under the map (upper half: the sky), in
    Radiance's convention: values x 683/179 are Radiance radiances, and lux = 179 x sum(Y cos dw)."""
    to_radiance = 683.0 / 179.0
    e = 0.0
    for j in range(h // 2):
        el = math.radians(90.0 - (j + 0.5) * 180.0 / h)
        dw = (2 * math.pi / w) * (math.pi / h) * math.cos(el)
        row = sum(yrow[0] * r + yrow[1] * g + yrow[2] * b for r, g, b in px[j * w:(j + 1) * w])
        e += row * to_radiance * math.sin(el) * dw
    return 179.0 * e


def exr_primaries(space):
    """The chromaticities firmament writes into an EXR of that colour space (`firmament info`)."""
    exr = os.path.join(work, "c.exr")
    subprocess.run([FM, "render", "--width", "16", "--quality", "preview", "--colorspace", space, "-o", exr], check=True)
    line = [l for l in subprocess.run([FM, "info", exr], capture_output=True, text=True, check=True).stdout.splitlines()
            if l.startswith("chromaticities")][0]
    return [float(v) for v in line.split(":", 1)[1].replace("(", " ").replace(")", " ").replace(",", " ").split()
            if v[0].isdigit() or v[0] == "-"]


work = tempfile.mkdtemp()
try:
    PRIMARIES = {s: exr_primaries(s) for s in ("Linear Rec.709", "ACEScg")}
    check(PRIMARIES["Linear Rec.709"] == [0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329], "Rec.709 chromaticities")
    oiio = shutil.which("oiiotool")
    print("reader:", "oiiotool (OpenImageIO)" if oiio else "this test's own RGBE decoder (no oiiotool)")
    for space, disk in (("Linear Rec.709", False), ("ACEScg", False), ("Linear Rec.709", True)):
        out = os.path.join(work, "sky.hdr")
        args = [FM, "render", "--preset", "clear-noon", "--width", "512", "--quality", "preview",
                "--colorspace", space, "-o", out]
        subprocess.run(args + ([] if disk else ["--no-sun-disk"]), check=True)
        side = json.load(open(os.path.join(work, "sky.json")))
        header, w, h, px = header_and_pixels(out)
        check(header[0] == "#?RADIANCE", "first line %r" % header[0])
        check("FORMAT=32-bit_rle_rgbe" in header, "no FORMAT line")
        check("EXPOSURE=1" in header, "no EXPOSURE=1")
        prim = [l for l in header if l.startswith("PRIMARIES=")]
        p = [float(v) for v in prim[0][10:].split()] if prim else []
        check(len(p) == 8 and all(abs(a - b) < 2e-4 for a, b in zip(p, PRIMARIES[space])),
              "%s: PRIMARIES %s" % (space, prim))
        elev = [l for l in header if l.startswith("# firmament.parameters.sun_elevation_deg: ")]
        check(elev and abs(float(elev[0].split(": ")[1]) - side["parameters"]["sun_elevation_deg"]) < 1e-6,
              "the sun's elevation as a comment line")
        check((w, h) == (512, 256), "size %dx%d" % (w, h))
        if oiio:
            read = oiio_pixels(out, w, h)
            check(max(abs(a - b) for p1, p2 in zip(px, read) for a, b in zip(p1, p2)) <= 1e-6 * max(max(p) for p in px) + 0.5 ** 8 * max(max(p) for p in px),
                  "%s: OpenImageIO reads other values" % space)
            px = read
        lux = card_lux(px, w, h, luminance_row(p or PRIMARIES[space]))
        key = "global_horizontal_illuminance_lux" if disk else "diffuse_horizontal_illuminance_lux"
        want = side["sky"][key]
        print("%s%s: card %.1f lux from the .hdr, sidecar %s %.1f lux (%+.3f%%)"
              % (space, ", with the disk" if disk else "", lux, key, want, 100 * (lux / want - 1)))
        check(abs(lux / want - 1) < 0.01, "%s: card %.1f lux vs sidecar %.1f" % (space, lux, want))
    # refused: an EXR option with a Radiance picture, nothing written
    r = subprocess.run([FM, "render", "--half", "-o", os.path.join(work, "x.hdr")], capture_output=True, text=True)
    check(r.returncode == 2 and r.stderr.count("\n") == 1 and not os.path.exists(os.path.join(work, "x.hdr")),
          "--half with .hdr: %d %r" % (r.returncode, r.stderr))
finally:
    shutil.rmtree(work)
print("test_radiance: %d failures" % len(failures))
sys.exit(1 if failures else 0)

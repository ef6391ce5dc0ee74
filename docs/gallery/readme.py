"""Writes the gallery's README.md from the renders' own sidecars, so that every caption states the
parameters that made its image.  Run by docs/gallery/render:

  readme.py WORK STAGE --sunset-exposure EV --version TEXT --seconds BIOMES DAY COURTYARD
            --threads N [--quick]

WORK holds biomes/NAME.json, day/paris_NNNN.json and courtyard.json; STAGE the images (checked to
exist) and receives README.md."""

import argparse
import glob
import json
import os

BIOME_COLUMNS = 3
DAY_COLUMNS = 4


def load(path):
    with open(path) as f:
        return json.load(f)


def deg(x, digits=1):
    return "%.*f°" % (digits, x)


def lux(x):
    return "{:,.0f} lx".format(x).replace(",", " ") if x >= 10 else "%.2g lx" % x


def image(stage, rel, alt):
    if not os.path.isfile(os.path.join(stage, rel)):
        raise SystemExit("readme.py: %s is missing" % rel)
    return "![%s](%s)" % (alt, rel)


def grid(cells, columns):
    """A Markdown table of (image, caption) cells, `columns` wide, captions under the images."""
    lines = ["|" + " |" * columns, "|" + "---|" * columns]
    for i in range(0, len(cells), columns):
        row = cells[i:i + columns] + [("", "")] * (columns - len(cells[i:i + columns]))
        lines.append("| " + " | ".join("%s<br>%s" % c if c[0] else "" for c in row) + " |")
    return "\n".join(lines)


def camera_text(cam, width, height):
    if cam["type"] == "pinhole":
        return ("pinhole, %s horizontal x %s vertical field of view, looking at azimuth %s, %s up, %d x %d"
                % (deg(cam["horizontal_fov_deg"], 0), deg(cam["vertical_fov_deg"]), deg(cam["look_azimuth_deg"], 0),
                   deg(cam["look_elevation_deg"], 0), width, height))
    if cam["type"] == "fisheye":
        return ("fisheye (%s), the upper hemisphere, north up and east left (as seen lying on one's back), %d x %d"
                % (cam.get("fisheye_projection", "equidistant"), width, height))
    return "%s, %d x %d" % (cam["type"], width, height)


def biomes_section(work, stage, ev):
    sides = sorted(glob.glob(os.path.join(work, "biomes", "*.json")))
    first = load(sides[0])
    p, img = first["parameters"], first["image"]
    cells = []
    for path in sides:
        s = load(path)
        name = s["parameters"]["biome"]
        a = s["atmosphere"]
        cells.append((image(stage, "biomes/%s.png" % name, name),
                      "**%s**: AOD 550 %.3f, Ångström %.2f, ssa %.3f; direct sun %s"
                      % (name, a["aerosol_optical_depth_550nm"], a["aerosol_angstrom_exponent_440_870nm"],
                         a["aerosol_single_scattering_albedo_550nm"], lux(s["sun"]["direct_normal_illuminance_lux"]))))
    ozone = p["ozone_column_du"]
    return "\n".join([
        "## The nine biomes at sunset",
        "",
        "The same sun, %s up at azimuth %s (due west), for each aerosol biome at turbidity 1 and its own "
        "humidity; no date, so ozone %s DU and the Earth-Sun distance %s AU; ground albedo %s, observer at %s m. "
        "Camera: %s. Quality `%s`. **Exposure %+g EV for all nine** (chosen on `rural`), so their brightness "
        "compares directly: the dust and urban skies are darker, not just redder. Each caption gives the "
        "biome's aerosol optical depth at 550 nm, Ångström exponent (440-870 nm) and single-scattering albedo, "
        "and the direct normal illuminance of the sun (from the sidecar)."
        % (deg(p["sun_elevation_deg"], 0), deg(p["sun_azimuth_deg"], 0), ozone, p["earth_sun_distance_au"],
           p["ground_albedo"], p["observer_altitude_m"], camera_text(first["camera"], img["width"], img["height"]),
           p["quality"], ev),
        "",
        "```sh",
        "build/firmament render --biome rural --sun-elevation %g --sun-azimuth %g --camera pinhole --fov %g \\"
        % (p["sun_elevation_deg"], p["sun_azimuth_deg"], first["camera"]["horizontal_fov_deg"]),
        "    --look-azimuth %g --look-elevation %g --aspect 16:9 --width %d --quality %s -o rural.exr \\"
        % (first["camera"]["look_azimuth_deg"], first["camera"]["look_elevation_deg"], img["width"], p["quality"]),
        "    --preview rural.png --exposure %g" % ev,
        "```",
        "",
        grid(cells, BIOME_COLUMNS),
        "",
    ])


def day_section(work, stage):
    sides = [load(p) for p in sorted(glob.glob(os.path.join(work, "day", "paris_*.json")))]
    first, last = sides[0], sides[-1]
    p, sp, img = first["parameters"], first["solar_position"], first["image"]
    step = (minutes(sides[1]["parameters"]["time"]) - minutes(p["time"])) if len(sides) > 1 else 0
    cells = []
    for s in sides:
        t = s["parameters"]["time"][:5]
        cells.append((image(stage, "day/paris-%s.png" % t.replace(":", ""), t),
                      "**%s**: sun %s up, azimuth %s; %s"
                      % (t, deg(s["sun"]["elevation_deg"]), deg(s["sun"]["azimuth_deg"], 0),
                         lux(s["sky"]["global_horizontal_illuminance_lux"]))))
    a = first["atmosphere"]
    return "\n".join([
        "## A day in Paris in %d steps" % len(sides),
        "",
        "Paris (%.4f N, %.4f E), %s, local time UTC%s: sunrise %s, solar noon %s, sunset %s (NREL SPA, "
        "from the sidecar). One time series from %s to %s every %d minutes, one render command sharing the "
        "atmosphere's tables; the first and last frames have the sun just above the horizon. "
        "`%s` aerosols at turbidity %g (AOD 550 %.3f), ozone from the climatology of the date (%.0f DU), ground "
        "albedo %s. Camera: %s. Quality `%s`. **Exposure automatic per frame** (the log-average sky luminance "
        "mapped to 18%% grey): a fixed exposure would show the sunrise frames black beside noon, so the "
        "frames compare colour and the distribution of light, and each caption gives the local time, the "
        "sun and the global horizontal illuminance (from the sidecar) for the brightness."
        % (p["latitude_deg"], p["longitude_deg"], p["date"], p["utc_offset"], hhmm(sp["sunrise"]),
           hhmm(sp["solar_noon"]), hhmm(sp["sunset"]), p["time"][:5], last["parameters"]["time"][:5], step,
           p["biome"], p["turbidity"], a["aerosol_optical_depth_550nm"], a["ozone_column_du"], p["ground_albedo"],
           camera_text(first["camera"], img["width"], img["height"]), p["quality"]),
        "",
        "```sh",
        "build/firmament render --latitude %g --longitude %g --date %s --utc-offset %s \\"
        % (p["latitude_deg"], p["longitude_deg"], p["date"], p["utc_offset"]),
        "    --time-start %s --time-end %s --step %d --camera fisheye --width %d --quality %s \\"
        % (p["time"][:5], last["parameters"]["time"][:5], step, img["width"], p["quality"]),
        "    -o paris.exr --preview paris.png        # paris_0000.exr/.json/.png ... paris_%04d" % (len(sides) - 1),
        "```",
        "",
        grid(cells, DAY_COLUMNS),
        "",
        "All twelve on one sheet: %s" % image(stage, "day.png", "a day in Paris, contact sheet"),
        "",
    ])


def hhmm(hhmmss):
    """A local "HH:MM:SS" rounded to the minute."""
    h, m, sec = (int(x) for x in hhmmss.split(":"))
    t = (h * 60 + m + (sec >= 30)) % (24 * 60)
    return "%02d:%02d" % (t // 60, t % 60)


def minutes(hhmmss):
    h, m = hhmmss.split(":")[:2]
    return int(h) * 60 + int(m)


def courtyard_section(work, stage):
    c = load(os.path.join(work, "courtyard.json"))
    s = c["sky"]
    return "\n".join([
        "## The demo courtyard in Blender",
        "",
        image(stage, "courtyard-golden-hour.png", "the demo courtyard at golden hour"),
        "",
        "`scenes/demo_courtyard.py` (the U-shaped building the add-on's tests use; its 60 m paving widened "
        "to 30 km here, so that it meets the sky at the horizon), lit by the world the add-on generates "
        "(installed from `build/firmament_sky.zip`, Generate Sky run headless) with its shipped preset "
        "\"Golden hour\": Paris, %s %s UTC%s, sun %s up at azimuth %s (west-north-west, behind the camera "
        "on the right), `%s` aerosols at turbidity %g, ozone from the climatology, albedo %s; global "
        "horizontal illuminance %s. World map %d x %d at quality `%s`, sun mode \"Sun Lamp\" (the map "
        "without the disk plus the matching Sun lamp). Blender %s, Cycles on the CPU, %d x %d, %d samples "
        "(adaptive), at most %d bounces, no denoising (Debian's Blender is built without "
        "OpenImageDenoise), view transform %s, **exposure %.2f EV**: metered for a white card facing the sun "
        "(direct normal + diffuse horizontal illuminance, %s) by the sidecar's rule EV = log2(683 pi / E); "
        "the sidecar's own suggestion, %.2f EV, meters a horizontal card, which the sun 5 degrees up barely "
        "lights, and would clip the sunlit facades. Generate Sky took %.0f s, the render %.0f s."
        % (s["date"], s["time"][:5], s["utc_offset"], deg(c["sun_elevation_deg"], 2), deg(c["sun_azimuth_deg"]),
           s["biome"], s["turbidity"], round(s["ground_albedo"], 3), lux(c["global_horizontal_illuminance_lux"]),
           c["map_width"], c["map_width"] // 2, c["map_quality"], c["blender"], c["width"], c["height"],
           c["samples"], c["max_bounces"], c["view_transform"], c["exposure_ev"],
           lux(c["facing_sun_illuminance_lux"]), c["suggested_exposure_ev"], c["sky_seconds"],
           c["render_seconds"]),
        "",
    ])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("work")
    ap.add_argument("stage")
    ap.add_argument("--sunset-exposure", type=float, required=True)
    ap.add_argument("--version", required=True)
    ap.add_argument("--seconds", nargs=3, type=float, required=True)
    ap.add_argument("--threads", type=int, required=True)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    threads = "every core" if a.threads == 0 else "%d thread%s" % (a.threads, "" if a.threads == 1 else "s")
    head = [
        "# Gallery",
        "",
        "Rendered by %s with `docs/gallery/render`%s. Every sky image is the 8-bit sRGB preview "
        "(`--preview`: OpenColorIO display `sRGB`, view `Standard`, values above 1 clip) of an EXR that is "
        "not kept; the captions below are written from the renders' sidecars."
        % (a.version, " **--quick** (tiny, preview quality: a trial run, not the gallery)" if a.quick else ""),
        "",
        "Regenerate the whole gallery (installs what is missing with apt, builds `build/`, renders into "
        "temporary folders and replaces the images and this file only when everything succeeded):",
        "",
        "```sh",
        "docs/gallery/render                 # every core",
        "docs/gallery/render --threads 1",
        "docs/gallery/render --quick --out /tmp/gallery   # a trial in about a minute, elsewhere",
        "```",
        "",
        "This run (%s): biomes %.0f s, the day %.0f s, the courtyard %.0f s (Generate Sky and Cycles)."
        % (threads, a.seconds[0], a.seconds[1], a.seconds[2]),
        "",
    ]
    text = "\n".join(head + [biomes_section(a.work, a.stage, a.sunset_exposure), day_section(a.work, a.stage),
                             courtyard_section(a.work, a.stage)])
    out = os.path.join(a.stage, "README.md")
    with open(out + ".tmp", "w") as f:
        f.write(text)
    os.replace(out + ".tmp", out)


if __name__ == "__main__":
    main()

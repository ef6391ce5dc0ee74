"""The sky settings (a plain dict of the add-on's property values) -> a checked argument list for
`firmament render`.  No bpy here."""

import datetime
import math

from . import options

SUN_MODES = ("LAMP", "DISK", "LAMP_CAMERA_DISK")


class SettingsError(ValueError):
    pass


def format_utc_offset(hours):
    minutes = int(round(hours * 60.0))
    sign = "+" if minutes >= 0 else "-"
    minutes = abs(minutes)
    return "%s%02d:%02d" % (sign, minutes // 60, minutes % 60)


def validate(s, opts):
    """Raises SettingsError naming the first bad setting.  opts: the executable's table of options
    (options.load), the source of the ranges, biome names and quality levels."""
    for key, (lo, hi, lo_open) in sorted(options.ranges(opts).items()):
        if key not in s:
            continue
        v = s[key]
        if not (isinstance(v, (int, float)) and math.isfinite(v) and (lo < v if lo_open else lo <= v) and v <= hi):
            raise SettingsError("%s: %r is outside %s%g, %g]" % (key.replace("_", " "), v, "(" if lo_open else "[", lo, hi))
    if not -12.0 <= s["utc_offset"] <= 14.0:
        raise SettingsError("UTC offset: %r is outside [-12, 14] hours" % s["utc_offset"])
    if s["biome"] not in options.choices(opts, "--biome"):
        raise SettingsError("biome: unknown '%s' (known: %s)" % (s["biome"], ", ".join(options.choices(opts, "--biome"))))
    cloud = s.get("cloud", "none")  # a list or a cloud file (from a preset) is the executable's to check
    if not any(c in cloud for c in ",/\\") and cloud not in ["none"] + options.choices(opts, "--cloud"):
        raise SettingsError("cloud: unknown '%s' (known: none, %s)" % (s["cloud"], ", ".join(options.choices(opts, "--cloud"))))
    if s["quality"] not in options.choices(opts, "--quality"):
        raise SettingsError("quality: unknown '%s'" % s["quality"])
    if s["sun_mode"] not in SUN_MODES:
        raise SettingsError("sun mode: unknown '%s'" % s["sun_mode"])
    if s["resolution"] % 2:
        raise SettingsError("resolution: %r is not even" % (s["resolution"],))
    try:
        datetime.date(s["year"], s["month"], s["day"])
    except (ValueError, TypeError):
        raise SettingsError("date: %r-%r-%r is not a real date" % (s["year"], s["month"], s["day"])) from None
    if not 1900 <= s["year"] <= 2100:
        raise SettingsError("date: year %d is outside 1900-2100" % s["year"])
    if not (0 <= s["hour"] <= 23 and 0 <= s["minute"] <= 59 and 0 <= s["second"] <= 59):
        raise SettingsError("time: %r:%r:%r is not a time of day" % (s["hour"], s["minute"], s["second"]))


def build_arguments(executable, opts, s, output, sidecar, disk_map=None):
    """The argument list (executable first) that renders settings s to output (EXR) and sidecar;
    disk_map: with sun mode LAMP_CAMERA_DISK, the second map that holds the disk."""
    validate(s, opts)
    args = [executable, "render", "--progress", "json", "-o", output, "--sidecar", sidecar]
    date = "%04d-%02d-%02d" % (s["year"], s["month"], s["day"])
    if s["sun_source"] == "TIME":
        args += ["--date", date, "--time", "%02d:%02d:%02d" % (s["hour"], s["minute"], s["second"]),
                 "--utc-offset", format_utc_offset(s["utc_offset"]),
                 "--latitude", repr(float(s["latitude"])), "--longitude", repr(float(s["longitude"]))]
    else:
        # the date sets the Earth-Sun distance, as with a clock time
        args += ["--sun-elevation", repr(float(s["sun_elevation"])),
                 "--sun-azimuth", repr(float(s["sun_azimuth"])), "--date", date]
        if s["ozone_mode"] == "AUTO":  # the climatology's column depends on the date and the place
            args += ["--latitude", repr(float(s["latitude"])), "--longitude", repr(float(s["longitude"]))]
    args += aerosol_options(s) + cloud_options(s)
    if s["ozone_mode"] == "MANUAL":
        args += ["--ozone-du", repr(float(s["ozone_du"]))]
    args += ["--albedo", repr(float(s["albedo"])), "--altitude", repr(float(s["altitude"])),
             "--width", str(s["resolution"]), "--quality", s["quality"], "--threads", str(s["threads"])]
    if s["sun_mode"] == "LAMP":
        args += ["--no-sun-disk"]
    elif s["sun_mode"] == "LAMP_CAMERA_DISK":
        if not disk_map:
            raise SettingsError("sun mode 'lamp + disk for the camera' needs a disk map path")
        args += ["--sun-disk-map", disk_map]
    return args


def series_plan(s):
    """(start, end, step) in minutes and the number of maps of a baked day.  With bake_timing STEP,
    one every s["bake_step_min"] minutes from s["bake_start"] to at most s["bake_end"] (clock hours,
    the end included when it falls on a step); with FRAME_RANGE, s["bake_frames"] maps from start to
    exactly end: map i at start + i (end - start) / (frames - 1), frame frame_start + i."""
    start, end = round(s["bake_start"] * 60), round(s["bake_end"] * 60)
    if s.get("bake_timing", "STEP") == "FRAME_RANGE":
        frames = s["bake_frames"]
        if frames < 2:
            raise SettingsError("bake a day over the frame range: it has %d frame; it needs at least 2" % frames)
        return start, end, (end - start) / (frames - 1), frames
    step = s["bake_step_min"]
    if not 1 <= step <= 720:
        raise SettingsError("bake a day: step %r min is outside [1, 720]" % step)
    return start, end, step, (end - start) // step + 1


def format_clock(hours):
    minutes = int(round(hours * 60.0))
    return "%02d:%02d" % (minutes // 60, minutes % 60)


def build_series_arguments(executable, opts, s, output, sidecar):
    """The argument list that renders a day (series_plan) on the settings' date and place,
    OUTPUT_0000.exr, ... each with its sidecar; always without the disk (the lamp is keyframed per
    frame)."""
    if s["sun_source"] != "TIME":
        raise SettingsError("bake a day: set the sun from date, time and place (not angles)")
    if not (0.0 <= s["bake_start"] < s["bake_end"] <= 24.0 - 1.0 / 60.0):
        raise SettingsError("bake a day: start %s must be before end %s within the day"
                            % (format_clock(s["bake_start"]), format_clock(s["bake_end"])))
    _start, _end, step, _frames = series_plan(s)
    one = dict(s, sun_mode="LAMP")
    args = build_arguments(executable, opts, one, output, sidecar)
    i = args.index("--time")
    # a fractional step is passed exactly (repr): the executable counts the maps from it, the end included
    args[i:i + 2] = ["--time-start", format_clock(s["bake_start"]), "--time-end", format_clock(s["bake_end"]),
                     "--step", str(step) if isinstance(step, int) else repr(step)]
    return args


def aerosol_options(s):
    """--biome and the aerosol amount and humidity of settings s."""
    args = ["--biome", s["biome"]]
    if s["biome"] != "none":
        if s["aerosol_amount"] == "AOD":
            args += ["--aod550", repr(float(s["aod550"]))]
        else:
            args += ["--turbidity", repr(float(s["turbidity"]))]
        if s["use_humidity"]:
            args += ["--humidity", repr(float(s["humidity"]))]
    return args


def cloud_options(s):
    """--cloud, its amount and height, and --fog-visibility of settings s (docs/clouds.md)."""
    args = []
    if s.get("cloud", "none") != "none":
        args += ["--cloud", s["cloud"]]
        if s["cloud_amount"] == "TAU":
            args += ["--cloud-tau", repr(float(s["cloud_tau"]))]
        elif s["cloud_amount"] == "LWP":
            args += ["--cloud-lwp", repr(float(s["cloud_lwp"]))]
        if s["use_cloud_height"]:
            args += ["--cloud-base", repr(float(s["cloud_base"])), "--cloud-thickness", repr(float(s["cloud_thickness"]))]
    if s.get("use_fog"):
        args += ["--fog-visibility", repr(float(s["fog_visibility"]))]
    return args


def atmosphere_arguments(executable, s):
    """`firmament render --print-atmosphere`: the sidecar's AOD 550, visibility and cloud optical depth
    without a render."""
    return [executable, "render", "--print-atmosphere"] + aerosol_options(s) + cloud_options(s)


def sun_arguments(executable, s):
    """`firmament sun --json` for the settings' date, local time and place."""
    return [executable, "sun", "--json", "--date", "%04d-%02d-%02d" % (s["year"], s["month"], s["day"]),
            "--time", "%02d:%02d:%02d" % (s["hour"], s["minute"], s["second"]),
            "--utc-offset", format_utc_offset(s["utc_offset"]), "--latitude", repr(float(s["latitude"])),
            "--longitude", repr(float(s["longitude"])), "--altitude", repr(float(s["altitude"]))]

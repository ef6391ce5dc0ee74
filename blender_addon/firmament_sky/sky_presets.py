"""Sky presets: the JSON schema shared with `firmament render --preset` (docs/cli.md, "Sky
presets").  Reading checks every key, type and range and names the file and JSON path of a
problem; writing produces a file the executable accepts.  No bpy here."""

import datetime
import json
import os
import re

TEXT_KEYS = ("name", "description")  # the preset's own; every other key is an option's preset_key


def _schema(opts):
    """{key: option or None} of the preset schema: the executable's options that have a preset key
    (the sky, and the view of a job in scenes/thesis/, which the add-on checks but does not use)."""
    keys = {k: None for k in TEXT_KEYS}
    keys.update({o["preset_key"]: o for o in opts.values() if o.get("preset_key")})
    return keys


class PresetError(ValueError):
    pass


def _bad(path, where, what):
    return PresetError("%s: %s: %s" % (path, where, what))


def _check(path, d, opts):
    if not isinstance(d, dict):
        raise _bad(path, "$", "must be an object")
    schema = _schema(opts)
    for key, value in d.items():
        where = "$." + key
        if key not in schema:
            raise _bad(path, where, "unknown key (known: %s)" % ", ".join(schema))
        o = schema[key]
        if o is not None and o.get("kind") in ("number", "whole"):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise _bad(path, where, "must be a number")
            lo, hi = o["min"], o["max"]
            if not ((lo < value) if o.get("min_open") else (lo <= value)) or value > hi:
                raise _bad(path, where, "%g is outside %s%g, %g]" % (value, "(" if o.get("min_open") else "[", lo, hi))
        elif not isinstance(value, str) or not value:
            raise _bad(path, where, "must be a non-empty string")
    if "name" not in d:
        raise _bad(path, "$", "missing 'name'")
    if "turbidity" in d and "aod550" in d:
        raise _bad(path, "$.aod550", "give turbidity or aod550, not both")
    if "cloud_tau" in d and "cloud_lwp" in d:
        raise _bad(path, "$.cloud_lwp", "give cloud_tau or cloud_lwp, not both")
    if "date" in d:
        m = re.fullmatch(r"(\d{4})-(\d{2})-(\d{2})", d["date"])
        try:
            if not m:
                raise ValueError
            datetime.date(int(m[1]), int(m[2]), int(m[3]))
        except ValueError:
            raise _bad(path, "$.date", "'%s' is not a date YYYY-MM-DD" % d["date"]) from None
    if "time" in d:
        m = re.fullmatch(r"(\d{1,2}):(\d{2})(?::(\d{2}))?", d["time"])
        if not m or int(m[1]) > 23 or int(m[2]) > 59 or int(m[3] or 0) > 59:
            raise _bad(path, "$.time", "'%s' is not a time HH:MM[:SS]" % d["time"])
    if "utc_offset" in d:
        m = re.fullmatch(r"([+-])(\d{2})(?::(\d{2}))?", d["utc_offset"])
        if not m or not -12 * 60 <= (int(m[2]) * 60 + int(m[3] or 0)) * (1 if m[1] == "+" else -1) <= 14 * 60:
            raise _bad(path, "$.utc_offset", "'%s' is not an offset +HH[:MM] in -12:00..+14:00" % d["utc_offset"])
    if "time" in d and "date" not in d:
        raise _bad(path, "$.time", "needs a date")
    if "time" in d and ("latitude" not in d or "longitude" not in d):
        raise _bad(path, "$.time", "needs latitude and longitude")


def read(path, opts):
    """The preset's dict, checked; PresetError names the file, line:column or JSON path."""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise PresetError("%s: cannot open: %s" % (path, e.strerror)) from None
    try:
        d = json.loads(text)
    except json.JSONDecodeError as e:
        raise PresetError("%s:%d:%d: JSON syntax error: %s" % (path, e.lineno, e.colno, e.msg)) from None
    _check(path, d, opts)
    return d


# A preset's number that also chooses how its quantity is given: key -> (the mode's property, value);
# in the order that settles a preset giving both (aod550 over turbidity).
_MODE_OF = {
    "turbidity": ("aerosol_amount", "TURBIDITY"),
    "aod550": ("aerosol_amount", "AOD"),
    "humidity": ("use_humidity", True),
    "cloud_tau": ("cloud_amount", "TAU"),
    "cloud_lwp": ("cloud_amount", "LWP"),
    "fog_visibility": ("use_fog", True),
    "ozone_du": ("ozone_mode", "MANUAL"),
}


def to_settings(d, defaults):
    """Settings (the add-on's property values) from a preset: defaults, then the preset's values."""
    s = dict(defaults)
    if "date" in d:
        s["year"], s["month"], s["day"] = (int(x) for x in d["date"].split("-"))
    if "time" in d:
        parts = [int(x) for x in d["time"].split(":")] + [0]
        s["hour"], s["minute"], s["second"] = parts[0], parts[1], parts[2]
        s["sun_source"] = "TIME"
    elif "sun_elevation" in d or "sun_azimuth" in d:
        s["sun_source"] = "ANGLES"
    if "utc_offset" in d:
        sign = -1.0 if d["utc_offset"][0] == "-" else 1.0
        hh, _, mm = d["utc_offset"][1:].partition(":")
        s["utc_offset"] = sign * (int(hh) + int(mm or 0) / 60.0)
    for key in ("latitude", "longitude", "sun_elevation", "sun_azimuth", "albedo", "altitude"):
        if key in d:
            s[key] = float(d[key])
    for key in ("biome", "cloud"):
        if key in d:
            s[key] = d[key]
    s["ozone_mode"] = "AUTO"
    for key, (mode, value) in _MODE_OF.items():
        if key in d:
            s[mode], s[key] = value, float(d[key])
    if "cloud_base" in d or "cloud_thickness" in d:
        s["use_cloud_height"] = True
        s["cloud_base"] = float(d.get("cloud_base", s["cloud_base"]))
        s["cloud_thickness"] = float(d.get("cloud_thickness", s["cloud_thickness"]))
    return s


def _num(x):
    """A property's value as typed: float32 noise dropped (-33.8688, not -33.86880111694336)."""
    return float("%.6g" % x)


def from_settings(name, s):
    """The preset dict for settings s (only what applies to the chosen modes), numbers rounded to
    the 6 significant digits a Blender float property holds."""
    d = {"name": name}
    d["date"] = "%04d-%02d-%02d" % (s["year"], s["month"], s["day"])
    d["latitude"], d["longitude"] = _num(s["latitude"]), _num(s["longitude"])
    if s["sun_source"] == "TIME":
        d["time"] = "%02d:%02d:%02d" % (s["hour"], s["minute"], s["second"])
        minutes = int(round(s["utc_offset"] * 60))
        d["utc_offset"] = "%s%02d:%02d" % ("+" if minutes >= 0 else "-", abs(minutes) // 60, abs(minutes) % 60)
    else:
        d["sun_elevation"], d["sun_azimuth"] = _num(s["sun_elevation"]), _num(s["sun_azimuth"])
    d["biome"] = s["biome"]
    if s["aerosol_amount"] == "AOD":
        d["aod550"] = _num(s["aod550"])
    else:
        d["turbidity"] = _num(s["turbidity"])
    if s["use_humidity"]:
        d["humidity"] = _num(s["humidity"])
    if s.get("cloud", "none") != "none":
        d["cloud"] = s["cloud"]
        if s["cloud_amount"] == "TAU":
            d["cloud_tau"] = _num(s["cloud_tau"])
        elif s["cloud_amount"] == "LWP":
            d["cloud_lwp"] = _num(s["cloud_lwp"])
        if s["use_cloud_height"]:
            d["cloud_base"], d["cloud_thickness"] = _num(s["cloud_base"]), _num(s["cloud_thickness"])
    if s.get("use_fog"):
        d["fog_visibility"] = _num(s["fog_visibility"])
    if s["ozone_mode"] == "MANUAL":
        d["ozone_du"] = _num(s["ozone_du"])
    d["albedo"], d["altitude"] = _num(s["albedo"]), _num(s["altitude"])
    return d


def write(path, d, opts):
    """Writes d (checked first) to path through a temporary file."""
    _check(path, d, opts)
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(d, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def display_name(path):
    """The preset's "name", or the file name when it cannot be read (the menu still lists it)."""
    try:
        with open(path, encoding="utf-8") as f:
            name = json.load(f).get("name")
        if isinstance(name, str) and name:
            return name
    except (OSError, ValueError, AttributeError):
        pass
    return os.path.splitext(os.path.basename(path))[0].replace("_", " ")

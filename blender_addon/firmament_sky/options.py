"""The executable's table of options (`firmament options --json`): the one source of the ranges,
biome names and quality levels that the add-on checks and offers.  No bpy here."""

import json
import os
import subprocess

# the add-on's settings whose option has no preset key of the same name
SETTING_OF_FLAG = {"--width": "resolution", "--threads": "threads", "--step": "bake_step_min"}

_cache = {}


class OptionsError(RuntimeError):
    pass


def load(executable):
    """{flag: option} of this executable (cached per path, modification time and presets folder)."""
    try:
        key = (executable, os.stat(executable).st_mtime_ns, os.environ.get("FIRMAMENT_PRESETS"))
    except OSError as e:
        raise OptionsError("cannot run %s: %s" % (executable, e.strerror)) from None
    if key not in _cache:
        try:
            r = subprocess.run([executable, "options", "--json"], stdin=subprocess.DEVNULL, capture_output=True,
                               text=True, timeout=30)
            table = json.loads(r.stdout) if r.returncode == 0 else None
            _cache[key] = {o["flag"]: o for o in table["options"]}
        except (OSError, subprocess.TimeoutExpired, ValueError, TypeError, KeyError) as e:
            raise OptionsError("%s options --json failed: %s" % (executable, e)) from None
        if r.returncode != 0:
            raise OptionsError("%s options --json failed: %s" % (executable, r.stderr.strip()))
    return _cache[key]


def ranges(opts):
    """{setting: (min, max, min_open)} for every numeric option the add-on sets."""
    out = {}
    for flag, o in opts.items():
        if o.get("kind") not in ("number", "whole") or "min" not in o:
            continue
        setting = SETTING_OF_FLAG.get(flag) or o.get("preset_key")
        if setting:
            out[setting] = (o["min"], o["max"], bool(o.get("min_open")))
    return out


def choices(opts, flag):
    """The names an option takes (e.g. --biome's built-in biomes, --quality's levels)."""
    return list(opts.get(flag, {}).get("choices", []))


def unit(opts, setting):
    """The unit the executable gives for a setting's option ("" when none)."""
    for flag, o in opts.items():
        if (SETTING_OF_FLAG.get(flag) or o.get("preset_key")) == setting:
            return o.get("unit", "")
    return ""

"""The sky settings, stored on the scene (scene.firmament_sky) so they travel with the .blend."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, StringProperty


_biome_items = []  # Blender keeps no reference to a dynamic enum's strings: this list does


def _biome_names(self, context):
    """The executable's built-in biomes (`firmament options --json`), and the current one."""
    from . import options, preferences
    try:
        names = options.choices(preferences.executable_and_options(context)[1], "--biome")
    except (preferences.NotFound, options.OptionsError):
        names = []
    return names if self.biome in names else [self.biome] + names


def _biome_items_of(self, context):
    _biome_items[:] = [(n, n.replace("-", " ").capitalize(),
                        "Aerosols of the '%s' biome (the executable's OPAC mixture): the sky's colour, haze and "
                        "how fast it whitens toward the horizon" % n, i)
                       for i, n in enumerate(_biome_names(self, context))]
    return _biome_items


_cloud_items = []


def _cloud_names(self, context):
    """"none" and the executable's cloud layers (presets/clouds/, `firmament options --json`)."""
    from . import options, preferences
    try:
        names = ["none"] + options.choices(preferences.executable_and_options(context)[1], "--cloud")
    except (preferences.NotFound, options.OptionsError):
        names = ["none"]
    return names if self.cloud in names else names + [self.cloud]


def _cloud_items_of(self, context):
    _cloud_items[:] = [("none", "None", "No clouds", 0)] + [
        (n, n.replace("-", " ").capitalize(),
         "A uniform layer of %s (presets/clouds/%s.json: its height and optical depth unless set below)" % (n, n), i)
        for i, n in enumerate(_cloud_names(self, context)) if n != "none"]
    return _cloud_items


def _menu_accessors(names_of, attr):
    """get and set of a dynamic enum that shows the string property attr among names_of's names."""
    def get(self):
        names = names_of(self, bpy.context)
        value = getattr(self, attr)
        return names.index(value) if value in names else 0

    def set_(self, value):
        names = names_of(self, bpy.context)
        if 0 <= value < len(names):
            setattr(self, attr, names[value])
    return get, set_


_get_biome, _set_biome = _menu_accessors(_biome_names, "biome")
_get_cloud, _set_cloud = _menu_accessors(_cloud_names, "cloud")


def _live_toggled(self, context):
    from . import live
    live.on_live_toggled(self, context)


class FirmamentSkySettings(bpy.types.PropertyGroup):
    # Ranges are the executable's (`firmament options --json`), set by register(): none are copied here.
    sun_source: EnumProperty(name="Sun From", items=[
        ("TIME", "Date, Time, Place", "The sun's position from the date, local clock time and place (NREL SPA)"),
        ("ANGLES", "Angles", "The sun's elevation and azimuth given directly"),
    ], default="TIME", description="How the sun's position is given")
    year: IntProperty(name="Year", default=2024, description="Date: the sun's path and the ozone of the season")
    month: IntProperty(name="Month", min=1, max=12, default=6, description="Date: month (1-12)")
    day: IntProperty(name="Day", min=1, max=31, default=21, description="Date: day of the month")
    hour: IntProperty(name="Hour", min=0, max=23, default=12,
                      description="Local clock time, hours: moves the sun (low sun: longer shadows, warmer light)")
    minute: IntProperty(name="Minute", min=0, max=59, default=0, description="Local clock time, minutes")
    second: IntProperty(name="Second", min=0, max=59, default=0, description="Local clock time, seconds")
    utc_offset: FloatProperty(name="UTC Offset (h)", min=-12.0, max=14.0, default=0.0, step=25, precision=2,
                              description="Local time minus UTC in hours, daylight saving time included "
                                          "(a wrong offset shifts the sun by 15 degrees per hour)")
    latitude: FloatProperty(name="Latitude (°N)", default=48.8566, precision=4,
                            description="Degrees north (south negative): how high the sun climbs")
    longitude: FloatProperty(name="Longitude (°E)", default=2.3522, precision=4,
                             description="Degrees east (west negative): when the sun crosses south")
    sun_elevation: FloatProperty(name="Sun Elevation (°)", default=30.0,
                                 description="Degrees above the horizon: lower is warmer, dimmer, longer shadows")
    sun_azimuth: FloatProperty(name="Sun Azimuth (°)", default=180.0,
                               description="Degrees from north toward east (180 = south): where shadows point away from")
    biome: StringProperty(name="Biome", default="rural", description="Aerosol environment (a built-in biome's name)")
    biome_menu: EnumProperty(name="Biome", items=_biome_items_of, get=_get_biome, set=_set_biome,
                             description="Aerosol environment: the sky's colour, haze and horizon brightness")
    aerosol_amount: EnumProperty(name="Aerosol Amount", items=[
        ("TURBIDITY", "Turbidity ×", "A multiplier of the biome's aerosol (1 = the biome as measured)"),
        ("AOD", "AOD 550", "The aerosol optical depth at 550 nm (0.05 very clear, 0.2 typical, 1 very hazy)"),
    ], default="TURBIDITY", description="How the amount of aerosol is given")
    turbidity: FloatProperty(name="Turbidity × Biome", soft_max=5.0, default=1.0,
                             description="Multiplies the biome's aerosol (1 = as measured, 2 = twice as hazy). Not "
                                         "Preetham/Hosek turbidity (2-10, 3 = clear): here 3 is three times the haze")
    aod550: FloatProperty(name="AOD 550", soft_max=2.0, default=0.2, precision=3,
                          description="Aerosol optical depth at 550 nm: more is hazier, whiter sky, softer sun")
    use_humidity: BoolProperty(name="Humidity", default=False,
                               description="Set the relative humidity (else the biome's own): humid aerosols grow "
                                           "and whiten the sky")
    humidity: FloatProperty(name="Humidity (%)", default=70.0,
                            description="Relative humidity in %: higher swells the aerosols, hazier horizon")
    cloud: StringProperty(name="Cloud", default="none", description="Cloud layer (a name in presets/clouds/), or none")
    cloud_menu: EnumProperty(name="Clouds", items=_cloud_items_of, get=_get_cloud, set=_set_cloud,
                             description="A horizontally uniform cloud layer: overcast decks dim and hide the sun, "
                                         "thin cirrostratus keeps it with a bright halo of light around it")
    cloud_amount: EnumProperty(name="Cloud Amount", items=[
        ("DEFAULT", "Type's", "The cloud type's own optical depth (presets/clouds/)"),
        ("TAU", "Optical Depth", "Optical depth at 550 nm: 0.5 thin veil, 10 grey deck, 30+ dark overcast"),
        ("LWP", "Water Path", "Liquid water path in g/m^2 (water clouds): 100 g/m^2 of stratus is optical depth 22"),
    ], default="DEFAULT", description="How the amount of cloud is given")
    cloud_tau: FloatProperty(name="Optical Depth", default=10.0, soft_max=60.0,
                             description="Cloud optical depth at 550 nm: more is darker and hides the sun sooner")
    cloud_lwp: FloatProperty(name="Water Path (g/m²)", default=100.0, soft_max=400.0,
                             description="Liquid water path of the cloud in g/m^2")
    use_cloud_height: BoolProperty(name="Set Height", default=False,
                                   description="Set the layer's base and thickness (else the cloud type's own)")
    cloud_base: FloatProperty(name="Base (km)", default=1.0, precision=2,
                              description="Cloud base above the ground in km")
    cloud_thickness: FloatProperty(name="Thickness (km)", default=0.5, precision=2,
                                   description="Cloud layer thickness in km")
    use_fog: BoolProperty(name="Fog", default=False, description="A layer of ground fog (200 m deep)")
    fog_visibility: FloatProperty(name="Visibility (m)", default=300.0, soft_max=2000.0,
                                  description="Fog visibility in metres: how far a dark object can still be seen")
    ozone_mode: EnumProperty(name="Ozone Source", items=[
        ("AUTO", "Auto", "Total ozone column from the date and place (climatology)"),
        ("MANUAL", "Manual", "Total ozone column in Dobson units"),
    ], default="AUTO", description="Ozone colours the twilight sky blue: from the climatology or given")
    ozone_du: FloatProperty(name="Ozone (DU)", default=300.0,
                            description="Total ozone column in Dobson units: more gives a bluer twilight")
    albedo: FloatProperty(name="Ground Albedo", default=0.2, subtype="FACTOR",
                          description="Reflectance of the ground in the map: a brighter ground brightens the "
                                      "sky near the horizon and the map's lower half")
    altitude: FloatProperty(name="Observer Altitude", default=0.0, subtype="DISTANCE", unit="LENGTH",
                            description="Height of the viewpoint above the ground: higher sees a darker, bluer sky")
    resolution: IntProperty(name="Width (px)", default=1024,
                            description="Map width in pixels (even; height = width / 2): sharper horizon, longer render")
    quality: EnumProperty(name="Quality", items=[
        ("preview", "Preview", "Seconds: for look development (some noise)"),
        ("final", "Final", "Low noise: for final renders"),
        ("reference", "Reference", "Per-pixel path tracing: slow, for validation"),
    ], default="preview", description="Noise against render time of the map")
    sun_mode: EnumProperty(name="Sun", items=[
        ("LAMP", "Sun Lamp", "Sky without the sun disk plus a matching Sun lamp: clean, works in EEVEE"),
        ("DISK", "Disk in Map", "The sun disk in the map, no lamp (Cycles; noisier shadows)"),
        ("LAMP_CAMERA_DISK", "Lamp + Visible Disk", "Lamp for lighting, the disk visible to the camera only"),
    ], default="LAMP", description="How the sun lights the scene (never counted twice)")
    camera_disk: BoolProperty(name="Sun Disk Seen by the Camera", default=True,
                               description="With the Sun Lamp: the camera sees the sun's disk (the lamp does the "
                                           "lighting; reflections and lighting never see it twice)")
    north_offset: FloatProperty(name="North Offset", subtype="ANGLE", unit="ROTATION", default=0.0,
                                soft_min=-3.14159, soft_max=3.14159,
                                description="Rotates the sky and sun: compass azimuth A appears at scene azimuth "
                                            "A + offset (as in the Sun Position add-on; +Y is north at 0)")
    apply_exposure: BoolProperty(name="Set Exposure", default=False,
                                 description="On Generate Sky, set the scene's film exposure by the metering below "
                                             "(off: your exposure stays; the suggestion is shown with an Apply button)")
    metering: EnumProperty(name="Metering", items=[
        ("HORIZONTAL", "Horizontal Card", "A white horizontal card shows as 1.0: every sky looks equally bright"),
        ("SUN_FACING", "Sun-Facing Card", "A white card facing the sun shows as 1.0"),
        ("SKY", "Sky Average", "The sky's average luminance shows as 0.18: low suns stay dark, as the eye sees them"),
    ], default="HORIZONTAL", description="What the suggested exposure makes look right")
    sky_strength: FloatProperty(name="Sky Strength ×", min=0.0, soft_max=4.0, default=1.0,
                                description="Multiplies the sky's light (1 = physical)")
    sun_strength: FloatProperty(name="Sun Strength ×", min=0.0, soft_max=4.0, default=1.0,
                                description="Multiplies the sun lamp's light (1 = physical)")
    ground: EnumProperty(name="Ground Below Horizon", items=[
        ("MAP", "From the Map", "The map's own ground (a uniform grey of the ground albedo)"),
        ("COLOUR", "Colour", "A ground of the colour below, lit by this sky (hides the grey band past a finite ground plane)"),
        ("BLACK", "Hidden", "Nothing below the horizon (black)"),
    ], default="MAP", description="What the world shows below the horizon")
    ground_colour: FloatVectorProperty(name="Ground Colour", subtype="COLOR", size=3, min=0.0, max=1.0,
                                       default=(0.25, 0.22, 0.18),
                                       description="Reflectance of the ground seen below the horizon")
    keep_maps_with_file: BoolProperty(
        name="Keep Maps With the File", default=True,
        description="On save, copy the maps beside the .blend (//firmament/) and reference them by relative "
                    "paths, so that the project can be moved or sent as one folder")
    bake_timing: EnumProperty(name="Frames", items=[
        ("STEP", "Every Step", "One frame every Step minutes from From to To; the scene's frame range becomes the day's"),
        ("FRAME_RANGE", "Scene's Frame Range", "The scene's frames, start to end, mapped linearly to the clock "
                                               "times From to To: one map per frame, the frame range kept"),
    ], default="STEP", description="Bake a day: which frames get which clock time")
    bake_start: FloatProperty(name="From (h)", min=0.0, max=23.99, default=6.0, precision=2,
                              description="Bake a day: the first frame's local clock time, hours")
    bake_end: FloatProperty(name="To (h)", min=0.0, max=23.99, default=20.0, precision=2,
                            description="Bake a day: the last frame's local clock time, hours (at most, with "
                                        "Every Step; exactly, with the scene's frame range)")
    bake_step_min: IntProperty(name="Step (min)", default=30,
                               description="Bake a day: minutes between frames (one map per frame)")
    threads: IntProperty(name="Threads", default=0, description="Worker threads of the executable; 0 = all cores")
    live: BoolProperty(name="Live", default=False, update=_live_toggled,
                       description="Follow every change of the sky's settings (and their keyframes) in the "
                                   "viewport with a 512 x 256 preview map and the lamp; renders still use "
                                   "final maps")
    # results, for the panel
    suggested_exposure_ev: FloatProperty(name="Suggested Exposure", default=0.0)
    aod550_result: FloatProperty(name="AOD 550 of the Last Map", default=-1.0)
    has_result: BoolProperty(default=False)
    last_message: StringProperty(default="")


SETTING_KEYS = ("sun_source", "year", "month", "day", "hour", "minute", "second", "utc_offset", "latitude",
                "longitude", "sun_elevation", "sun_azimuth", "biome", "aerosol_amount", "turbidity", "aod550",
                "use_humidity", "humidity", "cloud", "cloud_amount", "cloud_tau", "cloud_lwp", "use_cloud_height",
                "cloud_base", "cloud_thickness", "use_fog", "fog_visibility", "ozone_mode", "ozone_du", "albedo",
                "altitude", "resolution",
                "quality", "sun_mode", "north_offset", "apply_exposure", "metering", "threads", "bake_timing",
                "bake_start", "bake_end", "bake_step_min", "sky_strength", "sun_strength", "ground", "ground_colour", "camera_disk")
# what a sky preset holds (the rest are render choices)
PRESET_KEYS = ("sun_source", "year", "month", "day", "hour", "minute", "second", "utc_offset", "latitude",
               "longitude", "sun_elevation", "sun_azimuth", "biome", "aerosol_amount", "turbidity", "aod550",
               "use_humidity", "humidity", "cloud", "cloud_amount", "cloud_tau", "cloud_lwp", "use_cloud_height",
               "cloud_base", "cloud_thickness", "use_fog", "fog_visibility", "ozone_mode", "ozone_du", "albedo",
               "altitude")

# what the live sky follows: the sky and how the world and lamp show it.  No update callbacks: a
# Python one makes Blender re-sync the whole scene at the next draw (live.watch polls these instead;
# docs/decisions/2026-12-07-blender-live-latency.md)
LIVE_KEYS = PRESET_KEYS + ("sun_mode", "camera_disk", "north_offset", "sky_strength", "sun_strength", "metering", "ground",
                           "ground_colour")


def live_values(p):
    """The LIVE_KEYS' values, to compare with a later pass's (the colour copied: not a live array)."""
    return tuple(tuple(p.ground_colour) if k == "ground_colour" else getattr(p, k) for k in LIVE_KEYS)


def to_dict(p):
    d = {k: getattr(p, k) for k in SETTING_KEYS}
    d["ground_colour"] = tuple(d["ground_colour"])
    return d


def defaults():
    """The properties' default values, as a settings dict."""
    rna = FirmamentSkySettings.bl_rna.properties
    d = {k: rna[k].default for k in SETTING_KEYS if k != "ground_colour"}
    d["ground_colour"] = tuple(rna["ground_colour"].default_array)
    return d


def assign(p, s, keys=PRESET_KEYS):
    for k in keys:
        setattr(p, k, s[k])


def set_ranges(opts):
    """Gives the settings the executable's ranges (before the class is registered)."""
    from . import options
    ann = FirmamentSkySettings.__annotations__
    for key, (lo, hi, lo_open) in options.ranges(opts).items():
        prop = ann.get(key)
        if prop is None or prop.function not in (FloatProperty, IntProperty):
            continue
        if prop.function is IntProperty:
            lo, hi = int(lo) + (1 if lo_open else 0), int(hi)
        ann[key] = prop.function(**dict(prop.keywords, min=lo, max=hi))


def register():
    bpy.types.Scene.firmament_sky = bpy.props.PointerProperty(type=FirmamentSkySettings)


def unregister():
    del bpy.types.Scene.firmament_sky


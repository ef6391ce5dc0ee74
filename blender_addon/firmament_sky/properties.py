"""The sky settings, stored on the scene (scene.firmament_sky) so they travel with the .blend."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import command

BIOME_ITEMS = [
    ("none", "None", "No aerosols: a purely molecular sky"),
    ("background", "Background", "Very clean free-troposphere air"),
    ("desert-dust", "Desert dust", "Mineral dust: whitish sky, weak colour dependence"),
    ("maritime-clean", "Maritime clean", "Sea salt over the open ocean"),
    ("maritime-mineral", "Maritime mineral", "Sea air carrying desert dust"),
    ("polar-antarctic", "Polar Antarctic", "Very clean Antarctic air"),
    ("polar-arctic", "Polar Arctic", "Arctic air with some haze"),
    ("remote-continental", "Remote continental", "Clean air far from cities"),
    ("rural", "Rural", "Typical countryside air"),
    ("urban", "Urban", "City air with absorbing soot"),
]


class FirmamentSkySettings(bpy.types.PropertyGroup):
    sun_source: EnumProperty(name="Sun from", items=[
        ("TIME", "Date, Time, Place", "The sun's position from the date, local time and place (NREL SPA)"),
        ("ANGLES", "Angles", "The sun's elevation and azimuth given directly"),
    ], default="TIME")
    year: IntProperty(name="Year", min=1900, max=2100, default=2024)
    month: IntProperty(name="Month", min=1, max=12, default=6)
    day: IntProperty(name="Day", min=1, max=31, default=21)
    hour: IntProperty(name="Hour", min=0, max=23, default=12, description="Local clock time")
    minute: IntProperty(name="Minute", min=0, max=59, default=0)
    second: IntProperty(name="Second", min=0, max=59, default=0)
    utc_offset: FloatProperty(name="UTC Offset", min=-12.0, max=14.0, default=0.0, step=25, precision=2,
                              description="Local time minus UTC in hours (include daylight saving time)")
    latitude: FloatProperty(name="Latitude", min=-90.0, max=90.0, default=48.8566, precision=4,
                            description="Degrees, north positive")
    longitude: FloatProperty(name="Longitude", min=-180.0, max=180.0, default=2.3522, precision=4,
                             description="Degrees, east positive")
    sun_elevation: FloatProperty(name="Sun Elevation", min=-90.0, max=90.0, default=30.0,
                                 description="Degrees above the horizon")
    sun_azimuth: FloatProperty(name="Sun Azimuth", min=-360.0, max=360.0, default=180.0,
                               description="Degrees from north toward east")
    biome: EnumProperty(name="Biome", items=BIOME_ITEMS, default="rural",
                        description="Aerosol environment (OPAC mixtures)")
    aerosol_amount: EnumProperty(name="Aerosol Amount", items=[
        ("TURBIDITY", "Turbidity", "Multiplier of the biome's aerosol density"),
        ("AOD", "AOD 550", "Aerosol optical depth at 550 nm"),
    ], default="TURBIDITY")
    turbidity: FloatProperty(name="Turbidity", min=0.0, max=50.0, soft_max=5.0, default=1.0,
                             description="Multiplier of the biome's aerosol density; 1 = nominal")
    aod550: FloatProperty(name="AOD 550", min=0.001, max=10.0, soft_max=2.0, default=0.2, precision=3)
    use_humidity: BoolProperty(name="Humidity", default=False,
                               description="Set the relative humidity (else the biome's own)")
    humidity: FloatProperty(name="Humidity %", min=0.0, max=99.0, default=70.0)
    ozone_mode: EnumProperty(name="Ozone", items=[
        ("AUTO", "Auto", "Total ozone column from the date and place (climatology)"),
        ("MANUAL", "Manual", "Total ozone column in Dobson units"),
    ], default="AUTO")
    ozone_du: FloatProperty(name="Ozone DU", min=0.0, max=1000.0, default=300.0)
    albedo: FloatProperty(name="Ground Albedo", min=0.0, max=1.0, default=0.2, subtype="FACTOR")
    altitude: FloatProperty(name="Observer Altitude", min=0.0, max=20000.0, default=0.0,
                            description="Metres above the ground")
    resolution: IntProperty(name="Resolution", min=16, max=16384, default=1024,
                            description="Map width in pixels (even; height = width / 2)")
    quality: EnumProperty(name="Quality", items=[
        ("preview", "Preview", "Seconds: for look development"),
        ("final", "Final", "Low noise: for final renders"),
        ("reference", "Reference", "Per-pixel path tracing: slow, for validation"),
    ], default="preview")
    sun_mode: EnumProperty(name="Sun", items=[
        ("LAMP", "Sun Lamp", "Sky without the sun disk plus a matching Sun lamp: clean, works in EEVEE"),
        ("DISK", "Disk in Map", "The sun disk in the map, no lamp (Cycles; noisier shadows)"),
        ("LAMP_CAMERA_DISK", "Lamp + Visible Disk", "Lamp for lighting, the disk visible to the camera only"),
    ], default="LAMP")
    north_offset: FloatProperty(name="North Offset", subtype="ANGLE", unit="ROTATION", default=0.0,
                                soft_min=-3.14159, soft_max=3.14159,
                                description="Rotates the sky and sun: compass azimuth A appears at scene azimuth "
                                            "A + offset (as in the Sun Position add-on; +Y is north at 0)")
    apply_exposure: BoolProperty(name="Set Exposure", default=True,
                                 description="Set the scene's film exposure to the sky's suggested exposure "
                                             "(reported when applied)")
    keep_maps_with_file: BoolProperty(
        name="Keep Maps With the File", default=True,
        description="On save, copy the maps beside the .blend (//firmament/) and reference them by relative "
                    "paths, so that the project can be moved or sent as one folder")
    bake_start: FloatProperty(name="From", min=0.0, max=23.99, default=6.0,
                              precision=2, description="Bake a day: the first frame's local clock time, hours")
    bake_end: FloatProperty(name="To", min=0.0, max=23.99, default=20.0, precision=2,
                            description="Bake a day: the last frame's local clock time at most, hours")
    bake_step_min: IntProperty(name="Step", min=1, max=720, default=30,
                               description="Bake a day: minutes between frames (one map per frame)")
    threads: IntProperty(name="Threads", min=0, max=256, default=0, description="0 = all cores")
    # results, for the panel
    suggested_exposure_ev: FloatProperty(name="Suggested Exposure", default=0.0)
    has_result: BoolProperty(default=False)
    last_message: StringProperty(default="")


SETTING_KEYS = ("sun_source", "year", "month", "day", "hour", "minute", "second", "utc_offset", "latitude",
                "longitude", "sun_elevation", "sun_azimuth", "biome", "aerosol_amount", "turbidity", "aod550",
                "use_humidity", "humidity", "ozone_mode", "ozone_du", "albedo", "altitude", "resolution",
                "quality", "sun_mode", "north_offset", "apply_exposure", "threads", "bake_start", "bake_end",
                "bake_step_min")
# what a sky preset holds (the rest are render choices)
PRESET_KEYS = ("sun_source", "year", "month", "day", "hour", "minute", "second", "utc_offset", "latitude",
               "longitude", "sun_elevation", "sun_azimuth", "biome", "aerosol_amount", "turbidity", "aod550",
               "use_humidity", "humidity", "ozone_mode", "ozone_du", "albedo", "altitude")


def to_dict(p):
    return {k: getattr(p, k) for k in SETTING_KEYS}


def defaults():
    """The properties' default values, as a settings dict."""
    rna = FirmamentSkySettings.bl_rna.properties
    return {k: rna[k].default for k in SETTING_KEYS}


def assign(p, s, keys=PRESET_KEYS):
    for k in keys:
        setattr(p, k, s[k])


def register():
    bpy.types.Scene.firmament_sky = bpy.props.PointerProperty(type=FirmamentSkySettings)


def unregister():
    del bpy.types.Scene.firmament_sky


assert set(command.BIOMES) == {b[0] for b in BIOME_ITEMS}

#include "args.h"
#include "numbers.h"
#include "time_args.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    OPT_SUN_ELEVATION = 256,
    OPT_SUN_AZIMUTH,
    OPT_ALTITUDE,
    OPT_ALBEDO,
    OPT_OZONE,
    OPT_WIDTH,
    OPT_QUALITY,
    OPT_SAMPLES,
    OPT_SAMPLE_SCALE,
    OPT_SEED,
    OPT_THREADS,
    OPT_NO_SUN_DISK,
    OPT_PROGRESS,
    OPT_WAVELENGTH,
    OPT_SIDECAR,
    OPT_COLORSPACE,
    OPT_LIST_COLORSPACES,
    OPT_PREVIEW,
    OPT_HALF,
    OPT_SPECTRAL,
    OPT_SUN_DISK_MAP,
    OPT_COMPRESSION,
    OPT_EXPOSURE,
    OPT_EARTH_SUN_DISTANCE,
    OPT_ATMOSPHERE,
    OPT_BIOME,
    OPT_TURBIDITY,
    OPT_AOD550,
    OPT_HUMIDITY,
    OPT_AEROSOL_PHASE,
    OPT_DATE,
    OPT_LATITUDE,
    OPT_LONGITUDE,
    /* the sun from the date and time */
    OPT_TIME,
    OPT_UTC_OFFSET,
    OPT_REFRACTION,
    OPT_PRESSURE,
    OPT_TEMPERATURE,
    OPT_DELTA_T,
    OPT_TIME_START,
    OPT_TIME_END,
    OPT_STEP,
    /* cameras */
    OPT_CAMERA,
    OPT_FISHEYE_PROJECTION,
    OPT_FOV,
    OPT_LOOK_AZIMUTH,
    OPT_LOOK_ELEVATION,
    OPT_ASPECT,
};

/* Each option with the library field it sets (for error messages). */
typedef struct option_doc {
    int id;
    const char *name;
    const char *field;
} option_doc;

static const option_doc docs[] = {
    {OPT_SUN_ELEVATION, "sun-elevation", "sun_elevation_deg"},
    {OPT_SUN_AZIMUTH, "sun-azimuth", "sun_azimuth_deg"},
    {OPT_ALTITUDE, "altitude", "observer_altitude_m"},
    {OPT_ALBEDO, "albedo", "ground_albedo"},
    {OPT_OZONE, "ozone-du", "ozone_column_du"},
    {OPT_EARTH_SUN_DISTANCE, "earth-sun-distance", "earth_sun_distance_au"},
    {OPT_BIOME, "biome", "biome"},
    {OPT_TURBIDITY, "turbidity", "turbidity"},
    {OPT_AOD550, "aod550", "aod550"},
    {OPT_HUMIDITY, "humidity", "humidity_percent"},
    {OPT_AEROSOL_PHASE, "aerosol-phase", "aerosol_phase"},
    {OPT_DATE, "date", "date"},
    {OPT_LATITUDE, "latitude", "latitude_deg"},
    {OPT_LONGITUDE, "longitude", "longitude_deg"},
    {OPT_WAVELENGTH, "wavelength", "wavelength_nm"},
    {OPT_ATMOSPHERE, "atmosphere", "atmosphere_file"},
    {OPT_WIDTH, "width", "width"},
    {OPT_QUALITY, "quality", "quality"},
    {OPT_SAMPLES, "samples", "reference_samples"},
    {OPT_SAMPLE_SCALE, "sample-scale", "sample_scale"},
    {OPT_SEED, "seed", "seed"},
    {OPT_THREADS, "threads", "threads"},
    {OPT_HALF, "half", "half"},
    {OPT_COMPRESSION, "compression", "compression"},
    {OPT_SPECTRAL, "spectral", "spectral"},
    {OPT_TIME, "time", "time"},
    {OPT_TIME, "time", "hour"},
    {OPT_UTC_OFFSET, "utc-offset", "utc_offset_min"},
    {OPT_REFRACTION, "refraction", "refraction"},
    {OPT_PRESSURE, "pressure", "pressure_mbar"},
    {OPT_TEMPERATURE, "temperature", "temperature_c"},
    {OPT_DELTA_T, "delta-t", "delta_t_s"},
    {OPT_CAMERA, "camera", "camera.type"},
    {OPT_FISHEYE_PROJECTION, "fisheye-projection", "camera.fisheye_projection"},
    {OPT_FOV, "fov", "camera.fov_deg"},
    {OPT_LOOK_AZIMUTH, "look-azimuth", "camera.look_azimuth_deg"},
    {OPT_LOOK_ELEVATION, "look-elevation", "camera.look_elevation_deg"},
    {OPT_ASPECT, "aspect", "camera.aspect"},
};

static const struct option long_options[] = {
    {"output", required_argument, NULL, 'o'},
    {"sun-elevation", required_argument, NULL, OPT_SUN_ELEVATION},
    {"sun-azimuth", required_argument, NULL, OPT_SUN_AZIMUTH},
    {"altitude", required_argument, NULL, OPT_ALTITUDE},
    {"albedo", required_argument, NULL, OPT_ALBEDO},
    {"ozone-du", required_argument, NULL, OPT_OZONE},
    {"earth-sun-distance", required_argument, NULL, OPT_EARTH_SUN_DISTANCE},
    {"biome", required_argument, NULL, OPT_BIOME},
    {"turbidity", required_argument, NULL, OPT_TURBIDITY},
    {"aod550", required_argument, NULL, OPT_AOD550},
    {"humidity", required_argument, NULL, OPT_HUMIDITY},
    {"aerosol-phase", required_argument, NULL, OPT_AEROSOL_PHASE},
    {"date", required_argument, NULL, OPT_DATE},
    {"latitude", required_argument, NULL, OPT_LATITUDE},
    {"longitude", required_argument, NULL, OPT_LONGITUDE},
    {"wavelength", required_argument, NULL, OPT_WAVELENGTH},
    {"atmosphere", required_argument, NULL, OPT_ATMOSPHERE},
    {"width", required_argument, NULL, OPT_WIDTH},
    {"quality", required_argument, NULL, OPT_QUALITY},
    {"samples", required_argument, NULL, OPT_SAMPLES},
    {"sample-scale", required_argument, NULL, OPT_SAMPLE_SCALE},
    {"seed", required_argument, NULL, OPT_SEED},
    {"threads", required_argument, NULL, OPT_THREADS},
    {"no-sun-disk", no_argument, NULL, OPT_NO_SUN_DISK},
    {"progress", required_argument, NULL, OPT_PROGRESS},
    {"sidecar", required_argument, NULL, OPT_SIDECAR},
    {"colorspace", required_argument, NULL, OPT_COLORSPACE},
    {"list-colorspaces", no_argument, NULL, OPT_LIST_COLORSPACES},
    {"preview", required_argument, NULL, OPT_PREVIEW},
    {"half", no_argument, NULL, OPT_HALF},
    {"spectral", required_argument, NULL, OPT_SPECTRAL},
    {"sun-disk-map", required_argument, NULL, OPT_SUN_DISK_MAP},
    {"compression", required_argument, NULL, OPT_COMPRESSION},
    {"exposure", required_argument, NULL, OPT_EXPOSURE},
    {"time", required_argument, NULL, OPT_TIME},
    {"utc-offset", required_argument, NULL, OPT_UTC_OFFSET},
    {"refraction", required_argument, NULL, OPT_REFRACTION},
    {"pressure", required_argument, NULL, OPT_PRESSURE},
    {"temperature", required_argument, NULL, OPT_TEMPERATURE},
    {"delta-t", required_argument, NULL, OPT_DELTA_T},
    {"time-start", required_argument, NULL, OPT_TIME_START},
    {"time-end", required_argument, NULL, OPT_TIME_END},
    {"step", required_argument, NULL, OPT_STEP},
    {"camera", required_argument, NULL, OPT_CAMERA},
    {"fisheye-projection", required_argument, NULL, OPT_FISHEYE_PROJECTION},
    {"fov", required_argument, NULL, OPT_FOV},
    {"look-azimuth", required_argument, NULL, OPT_LOOK_AZIMUTH},
    {"look-elevation", required_argument, NULL, OPT_LOOK_ELEVATION},
    {"aspect", required_argument, NULL, OPT_ASPECT},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

const char *options_flag_for(const char *field)
{
    static char flag[64];
    for (size_t i = 0; i < sizeof docs / sizeof docs[0]; i++)
        if (strcmp(docs[i].field, field) == 0) {
            snprintf(flag, sizeof flag, "--%s", docs[i].name);
            return flag;
        }
    return NULL;
}

void options_print_usage(void)
{
    fputs("usage: firmament render [options] [-o OUT.exr]\n"
          "       firmament sun --date YYYY-MM-DD --time HH:MM[:SS] --latitude DEG --longitude DEG\n"
          "                     [--utc-offset +HH[:MM]] [--altitude M] [--refraction on|off] [--pressure MBAR]\n"
          "                     [--temperature C] [--delta-t S] [--json]\n"
          "       firmament compare IMAGE.exr REFERENCE.exr [--exclude-sun DEG] [--json]\n"
          "       firmament info FILE.exr   (the EXR's header: standard and firmament.* attributes)\n"
          "       firmament --help | --version\n"
          "\n"
          "Renders the sky seen from one place as an equirectangular OpenEXR map (Blender's\n"
          "Environment Texture layout: north at u = 0.25, east at the centre, zenith at the top), or\n"
          "through a fisheye or pinhole camera, and a JSON sidecar with the sun's direction and light.\n"
          "Values are CIE-weighted radiance in linear Rec.709 or the --colorspace chosen (Y x 683 =\n"
          "cd/m^2), or spectral radiance with --wavelength.\n"
          "\n"
          "Sky:\n"
          "  --sun-elevation DEG    elevation of the sun's centre, [-90, 90] (default 30)\n"
          "  --sun-azimuth DEG      from north toward east, [-360, 360] (default 180, south)\n"
          "  --altitude M           observer above the ground, [0, 20000] (default 0)\n"
          "  --albedo X             Lambertian ground reflectance, [0, 1] (default 0.2)\n"
          "  --ozone-du X           total ozone column in Dobson units, [0, 1000]; 0 disables (default:\n"
          "                         from the climatology with --date, else 300)\n"
          "  --date YYYY-MM-DD      date (1900-2100) for the ozone climatology and, with --time, the sun;\n"
          "                         needs --latitude\n"
          "  --latitude DEG         [-90, 90], north positive\n"
          "  --longitude DEG        [-180, 180], east positive (default 0; needed with --time)\n",
          stdout);
    /* the sun from the date and time */
    fputs("Sun from the date and time (NREL SPA, +-0.0003 deg):\n"
          "  --time HH:MM[:SS]      local clock time on --date at --latitude, --longitude: sets the sun's\n"
          "                         apparent elevation and azimuth and the Earth-Sun distance of the day,\n"
          "                         unless --sun-elevation, --sun-azimuth or --earth-sun-distance are given\n"
          "  --utc-offset +-HH[:MM] local time minus UTC, -12:00 to +14:00 (default +00:00)\n"
          "  --refraction on|off    atmospheric refraction lifts the sun (default on; the disk stays round)\n"
          "  --pressure MBAR        air pressure for refraction, [0, 2000] (default 1010)\n"
          "  --temperature C        air temperature for refraction, [-100, 100] (default 10)\n"
          "  --delta-t S            TT - UT in seconds, [-8000, 8000] (default: Espenak & Meeus estimate)\n"
          "  --time-start HH:MM[:SS], --time-end HH:MM[:SS], --step MIN\n"
          "                         a time series instead of --time: one map every MIN minutes from start\n"
          "                         to end (inclusive, at most 10000), OUT_0000.exr, OUT_0001.exr, ... each\n"
          "                         with its sidecar; the atmosphere's tables are built once\n",
          stdout);
    fputs("Aerosols:\n"
          "  --biome NAME           none | background | desert-dust | maritime-clean | maritime-mineral |\n"
          "                         polar-antarctic | polar-arctic | remote-continental | rural | urban,\n"
          "                         or a biome JSON file (default rural)\n"
          "  --turbidity X          multiplier of the biome's aerosol number density, [0, 50] (default 1)\n"
          "  --aod550 X             instead: scale the biome to this aerosol optical depth at 550 nm\n"
          "  --humidity RH          relative humidity in %, [0, 99], for hygroscopic growth (default: the\n"
          "                         biome's)\n"
          "  --aerosol-phase MODEL  mie (tabulated Mie phase function, default) | hg (Henyey-Greenstein\n"
          "                         with the Mie asymmetry parameter)\n"
          "  --earth-sun-distance AU  [0.95, 1.05] (default 1)\n"
          "  --wavelength NM        monochromatic render at one wavelength, [300, 1000]: one channel of\n"
          "                         spectral radiance in W m^-2 sr^-1 nm^-1\n"
          "  --atmosphere FILE      a custom atmosphere (JSON, docs/atmosphere-file.md) instead of the\n"
          "                         built-in Earth: its planet, constituents and optionally its ground\n"
          "                         albedo (over --albedo) and solar spectrum; the options of the\n"
          "                         built-in ozone and aerosols are ignored;\n"
          "                         e.g. presets/atmospheres/reference-rayleigh.json\n"
          "Image:\n"
          "  -o, --output FILE      output EXR (default sky.exr); the sidecar is FILE with .json\n"
          "  --sidecar FILE         sidecar path instead of the default\n"
          "  --width W              even, [8, 16384]; height = W/2 for equirect, W for fisheye,\n"
          "                         W/aspect for pinhole (default 2048)\n"
          "  --no-sun-disk          leave the sun disk out of the map (its aureole stays)\n"
          "  --sun-disk-map FILE    also write FILE (an EXR, and its sidecar) with the disk, and leave the disk out\n"
          "                         of the main map: one render, sky for lighting and disk for the camera\n"
          "  --preset NAME|FILE     a sky preset (presets/skies/NAME.json or a JSON file): its settings\n"
          "                         apply as if given first, so explicit options override them\n",
          stdout);
    /* (in parts: C17 compilers need only accept string literals of 4095 characters) */
    fputs("Camera:\n"
          "  --camera TYPE          equirect (default) | fisheye | pinhole\n"
          "  --fisheye-projection P fisheye: equidistant (r ~ zenith angle, default) | equisolid\n"
          "                         (r ~ 2 sin(zenith angle / 2), equal-area); upward hemisphere in the\n"
          "                         inscribed circle, zenith at the centre, north up and east LEFT as seen\n"
          "                         looking up; pixels outside the circle are 0\n"
          "  --fov DEG              pinhole: horizontal field of view, (0, 170] (default 90)\n"
          "  --look-azimuth DEG     pinhole: view direction from north toward east, [-360, 360]\n"
          "                         (default 180, south)\n"
          "  --look-elevation DEG   pinhole: view direction above the horizontal, [-90, 90] (default 15);\n"
          "                         level horizon, no roll\n"
          "  --aspect W:H | X       pinhole: width / height, e.g. 16:9 or 1.5; height = W/aspect rounded\n"
          "                         to even, [8, 16384] (default 16:9)\n"
          "  --half                 16-bit half-float EXR; refused (exit 2) when a value exceeds 65504,\n"
          "                         as the sun disk does: add --no-sun-disk\n"
          "  --compression METHOD   zip | piz (lossless) | dwaa (lossy, half precision, level 45; not with\n"
          "                         the sun disk beyond 65504) (default piz)\n"
          "  --spectral FILE.exr    also write the spectral radiance (41 wavelengths, 380-780 nm) in the\n"
          "                         spectral OpenEXR layout of Fichet et al. 2021 (41 x the image memory)\n"
          "Colour (OpenColorIO; config $OCIO, else firmament's presets/ocio/config.ocio):\n"
          "  --colorspace NAME      scene-linear colour space of the EXR and of the sidecar's RGB values,\n"
          "                         any of the config's (default \"Linear Rec.709\"; e.g. ACEScg)\n"
          "  --list-colorspaces     print the config's colour spaces and exit\n"
          "  --preview FILE.png     also write an 8-bit sRGB preview (display \"sRGB\", view \"Standard\")\n"
          "  --exposure EV          preview exposure: values x 2^EV before the display transform, [-100, 100]\n"
          "                         (default: the sky's log-average luminance above the horizon -> 0.18)\n"
          "Quality:\n"
          "  --quality LEVEL        preview | final | reference (default final); final takes up to 2x\n"
          "                         its paths in deep twilight (sun -11 to -21 deg, most at -18)\n"
          "  --samples N            reference quality: paths per pixel (default 256; slow by design,\n"
          "                         about 3 us of one core per colour path)\n"
          "  --sample-scale X       multiply every sample count of the quality level, (0, 1024]\n"
          "  --seed N               random seed, [0, 2^53] (default 0): same seed and threads, same bits\n"
          "  --threads N            worker threads, [0, 256]; 0 = all cores (default 0)\n"
          "  --progress MODE        tty (bar on stderr) | json (lines on stdout) | none\n"
          "                         (default: tty when stderr is a terminal, else none)\n"
          "\n"
          "Exit status: 0 done, 1 runtime failure, 2 bad usage or input, 128+N stopped by signal N\n"
          "(130 for Ctrl-C).  An interrupted or failed run leaves no partial file and never replaces\n"
          "an existing one.\n",
          stdout);
}

/* ---- the sun from the date and time: --time, --utc-offset, refraction, time series ---------- */

typedef struct time_options {
    int time, start, end, step;                       /* given */
    int solar_only;                                   /* OPT_ of a refraction / Delta T option given */
    int sun_elevation, sun_azimuth, distance, longitude; /* given, for the overrides and checks */
} time_options;

#define FM_MAX_FRAMES 10000

static int parse_time_option(int c, const char *name, const char *arg, options *opt, time_options *t, char *msg,
                             size_t msg_size)
{
    char flag[32];
    snprintf(flag, sizeof flag, "--%s", name);
    int seconds = 0, on = 0;
    double d = 0.0;
    switch (c) {
    case OPT_TIME:
    case OPT_TIME_START:
    case OPT_TIME_END:
        if (!parse_time_arg(flag, arg, &seconds, msg, msg_size))
            return 0;
        if (c == OPT_TIME_END) {
            opt->time_end_s = seconds;
            t->end = 1;
        } else {
            opt->time_start_s = seconds;
            *(c == OPT_TIME ? &t->time : &t->start) = 1;
        }
        return 1;
    case OPT_UTC_OFFSET:
        return parse_utc_offset_arg(flag, arg, &opt->sky.utc_offset_min, msg, msg_size);
    case OPT_REFRACTION:
        t->solar_only = c;
        if (!parse_on_off_arg(flag, arg, &on, msg, msg_size))
            return 0;
        opt->sky.refraction = on;
        return 1;
    case OPT_STEP:
        if (!parse_decimal(arg, &d) || !(d > 0.0)) {
            snprintf(msg, msg_size, "%s: '%s' is not a positive number of minutes", flag, arg);
            return 0;
        }
        opt->step_min = d;
        t->step = 1;
        return 1;
    default: /* pressure, temperature, Delta T: numbers, ranges checked by the library */
        t->solar_only = c;
        if (!parse_decimal(arg, &d)) {
            snprintf(msg, msg_size, "%s: '%s' is not a number", flag, arg);
            return 0;
        }
        *(c == OPT_PRESSURE ? &opt->sky.pressure_mbar
                            : (c == OPT_TEMPERATURE ? &opt->sky.temperature_c : &opt->sky.delta_t_s)) = d;
        return 1;
    }
}

static const char *option_name(int id)
{
    for (size_t i = 0; i < sizeof long_options / sizeof long_options[0] - 1; i++)
        if (long_options[i].val == id)
            return long_options[i].name;
    return "?";
}

static int finish_time_options(options *opt, const time_options *t, int have_latitude, char *msg, size_t msg_size)
{
    const char *first = t->time ? "--time" : (t->start ? "--time-start" : (t->end ? "--time-end" : "--step"));
    /* a given value equal to the library's "from the time" sentinel is out of range, not a request */
    const struct {
        int given;
        double v;
        const char *flag, *range;
    } sentinel[] = {{t->sun_elevation, opt->sky.sun_elevation_deg, "--sun-elevation", "[-90, 90] degrees"},
                    {t->sun_azimuth, opt->sky.sun_azimuth_deg, "--sun-azimuth", "[-360, 360] degrees"},
                    {t->distance, opt->sky.earth_sun_distance_au, "--earth-sun-distance", "[0.95, 1.05] AU"}};
    for (int i = 0; i < 3; i++)
        if (sentinel[i].given && sentinel[i].v == FM_SUN_FROM_TIME) {
            snprintf(msg, msg_size, "%s: %g is outside %s", sentinel[i].flag, sentinel[i].v, sentinel[i].range);
            return 0;
        }
    if (!(t->time || t->start || t->end || t->step)) {
        if (t->solar_only) {
            snprintf(msg, msg_size, "--%s: applies only with --time or --time-start", option_name(t->solar_only));
            return 0;
        }
        if (opt->sky.utc_offset_min != 0) {
            snprintf(msg, msg_size, "--utc-offset: applies only with --time or --time-start");
            return 0;
        }
        return 1;
    }
    if (t->time && (t->start || t->end || t->step)) {
        snprintf(msg, msg_size, "--time: give either --time or --time-start, --time-end and --step (a series)");
        return 0;
    }
    if (!t->time && !(t->start && t->end && t->step)) {
        snprintf(msg, msg_size, "%s: a time series needs --time-start, --time-end and --step", first);
        return 0;
    }
    if (opt->sky.year == 0) {
        snprintf(msg, msg_size, "%s: needs --date", first);
        return 0;
    }
    if (!have_latitude || !t->longitude) {
        snprintf(msg, msg_size, "%s: needs --latitude and --longitude", first);
        return 0;
    }
    if (!t->time) {
        char a[16], b[16];
        format_time_of_day(opt->time_start_s, a, sizeof a);
        format_time_of_day(opt->time_end_s, b, sizeof b);
        if (opt->time_start_s > opt->time_end_s) {
            snprintf(msg, msg_size, "--time-start: %s is after --time-end %s (a series stays within the date)", a, b);
            return 0;
        }
        double frames = floor((opt->time_end_s - opt->time_start_s) / (60.0 * opt->step_min) + 1e-9) + 1.0;
        if (frames > FM_MAX_FRAMES) {
            /* the count in full unless it is absurd (--step 1e-300 would print 300 digits) */
            snprintf(msg, msg_size, frames < 1e9 ? "--step: %g min from %s to %s makes %.0f frames (at most %d)"
                                                 : "--step: %g min from %s to %s makes %.3g frames (at most %d)",
                     opt->step_min, a, b, frames, FM_MAX_FRAMES);
            return 0;
        }
        opt->frames = (int)frames;
    }
    opt->sky.hour = opt->time_start_s / 3600;
    opt->sky.minute = opt->time_start_s / 60 % 60;
    opt->sky.second = opt->time_start_s % 60;
    /* what was not given comes from the time */
    if (!t->sun_elevation)
        opt->sky.sun_elevation_deg = FM_SUN_FROM_TIME;
    if (!t->sun_azimuth)
        opt->sky.sun_azimuth_deg = FM_SUN_FROM_TIME;
    if (!t->distance)
        opt->sky.earth_sun_distance_au = FM_SUN_FROM_TIME;
    return 1;
}

/* "W:H" or a number: width / height, positive. */
static int parse_aspect(const char *s, double *out)
{
    const char *colon = strchr(s, ':');
    double w, h;
    if (!colon)
        return parse_decimal(s, out) && *out > 0.0;
    char left[64];
    size_t n = (size_t)(colon - s);
    if (n == 0 || n >= sizeof left)
        return 0;
    memcpy(left, s, n);
    left[n] = '\0';
    if (!parse_decimal(left, &w) || !parse_decimal(colon + 1, &h) || !(w > 0.0) || !(h > 0.0))
        return 0;
    *out = w / h;
    return isfinite(*out) && *out > 0.0;
}

/* The camera options; returns 0 when c is not one of them, -1 on a bad value (msg filled), else 1.
 * *specific records the last option that belongs to one camera only, and that camera. */
static int camera_option(int c, const char *arg, options *opt, const char **specific, fm_camera_type *needs,
                         char *msg, size_t msg_size)
{
    fm_camera *cam = &opt->render.camera;
    switch (c) {
    case OPT_CAMERA:
        if (strcmp(arg, "equirect") == 0)
            cam->type = FM_CAMERA_EQUIRECT;
        else if (strcmp(arg, "fisheye") == 0)
            cam->type = FM_CAMERA_FISHEYE;
        else if (strcmp(arg, "pinhole") == 0)
            cam->type = FM_CAMERA_PINHOLE;
        else {
            snprintf(msg, msg_size, "--camera: '%s' is not one of equirect, fisheye, pinhole", arg);
            return -1;
        }
        return 1;
    case OPT_FISHEYE_PROJECTION:
        if (strcmp(arg, "equidistant") == 0)
            cam->fisheye_projection = FM_FISHEYE_EQUIDISTANT;
        else if (strcmp(arg, "equisolid") == 0)
            cam->fisheye_projection = FM_FISHEYE_EQUISOLID;
        else {
            snprintf(msg, msg_size, "--fisheye-projection: '%s' is not one of equidistant, equisolid", arg);
            return -1;
        }
        *specific = "fisheye-projection";
        *needs = FM_CAMERA_FISHEYE;
        return 1;
    case OPT_FOV:
    case OPT_LOOK_AZIMUTH:
    case OPT_LOOK_ELEVATION: {
        double *field = c == OPT_FOV ? &cam->fov_deg
                                     : (c == OPT_LOOK_AZIMUTH ? &cam->look_azimuth_deg : &cam->look_elevation_deg);
        const char *name = c == OPT_FOV ? "fov" : (c == OPT_LOOK_AZIMUTH ? "look-azimuth" : "look-elevation");
        if (!parse_decimal(arg, field)) {
            snprintf(msg, msg_size, "--%s: '%s' is not a number", name, arg);
            return -1;
        }
        *specific = name;
        *needs = FM_CAMERA_PINHOLE;
        return 1;
    }
    case OPT_ASPECT:
        if (!parse_aspect(arg, &cam->aspect)) {
            snprintf(msg, msg_size, "--aspect: '%s' is not a ratio W:H or a positive number", arg);
            return -1;
        }
        *specific = "aspect";
        *needs = FM_CAMERA_PINHOLE;
        return 1;
    default:
        return 0;
    }
}

/* The option's own word on the command line: where getopt_long found it (before its value when the
 * value came as the next word). */
static const char *option_token(char **argv, const char *arg)
{
    return arg && optind >= 2 && arg == argv[optind - 1] ? argv[optind - 2] : argv[optind - 1];
}

/* getopt_long also takes unique abbreviations (--pres for --pressure), which turn a typo of another
 * option (--pres meant --preset) into a different setting: only full names are accepted. */
static int abbreviated(char **argv, const char *name, const char *arg)
{
    const char *tok = option_token(argv, arg);
    if (strncmp(tok, "--", 2) != 0)
        return 0;
    size_t n = strcspn(tok + 2, "=");
    return !(n == strlen(name) && strncmp(tok + 2, name, n) == 0);
}

parse_result options_parse(int argc, char **argv, options *opt, char *msg, size_t msg_size)
{
    opt->sky = fm_sky_params_default();
    opt->render = fm_render_params_default();
    opt->output = "sky.exr";
    opt->sidecar = NULL;
    opt->colorspace = "Linear Rec.709";
    opt->list_colorspaces = 0;
    opt->preview = NULL;
    opt->half = 0;
    opt->spectral = NULL;
    opt->sun_disk_map = NULL;
    /* PIZ: a quarter smaller than ZIP level 1 on skies and faster to write (4096 x 2048 sun 30
     * final: 30.7 vs 41.2 MB, 3.56 vs 3.85 s), as fast for Blender to load (0.37 vs 0.41 s) */
    opt->compression = FM_EXR_PIZ;
    opt->exposure_ev = 0.0;
    opt->have_exposure = 0;
    opt->progress = PROGRESS_AUTO;

    opterr = 0; /* we print our own, one-line messages */
    optind = 1;
    int c, index = -1, have_ozone = 0, have_latitude = 0;
    time_options times = {0};
    opt->frames = 0;
    const char *builtin_only = NULL; /* an option about the built-in atmosphere that was given */
    const char *camera_specific = NULL; /* an option of one camera only that was given, and its camera */
    fm_camera_type camera_needed = FM_CAMERA_EQUIRECT;
    while ((c = getopt_long(argc, argv, ":o:h", long_options, &index)) != -1) {
        const char *name = index >= 0 ? long_options[index].name : NULL;
        const char *arg = optarg;
        if (name && abbreviated(argv, name, arg)) {
            snprintf(msg, msg_size, "unknown option '%s' (options are given in full: --%s?)", option_token(argv, arg),
                     name);
            return PARSE_ERROR;
        }
        int camera = camera_option(c, arg, opt, &camera_specific, &camera_needed, msg, msg_size);
        if (camera < 0)
            return PARSE_ERROR;
        if (camera > 0) {
            index = -1;
            continue;
        }
        double d = 0.0;
        long long n = 0;
        int bad_number = 0;
        if ((c == 'o' || c == OPT_SIDECAR || c == OPT_PREVIEW || c == OPT_SUN_DISK_MAP || c == OPT_SPECTRAL) &&
            arg[0] == '-' && arg[1] == '-') {
            /* `-o --width 64`: the path was left out and the next option taken for it */
            snprintf(msg, msg_size, "%s%s: '%s' looks like an option, not a file (a file of that name: ./%s)",
                     name ? "--" : "-o", name ? name : "", arg, arg);
            return PARSE_ERROR;
        }
        switch (c) {
        case 'o':
            opt->output = arg;
            break;
        case 'h':
            options_print_usage();
            return PARSE_EXIT_OK;
        case OPT_SUN_ELEVATION:
            times.sun_elevation = 1;
            bad_number = !parse_decimal(arg, &opt->sky.sun_elevation_deg);
            break;
        case OPT_SUN_AZIMUTH:
            times.sun_azimuth = 1;
            bad_number = !parse_decimal(arg, &opt->sky.sun_azimuth_deg);
            break;
        case OPT_ALTITUDE:
            bad_number = !parse_decimal(arg, &opt->sky.observer_altitude_m);
            break;
        case OPT_ALBEDO:
            bad_number = !parse_decimal(arg, &opt->sky.ground_albedo);
            break;
        case OPT_OZONE:
            bad_number = !parse_decimal(arg, &opt->sky.ozone_column_du);
            if (!bad_number && opt->sky.ozone_column_du < 0.0) { /* negative values are library sentinels */
                snprintf(msg, msg_size, "--ozone-du: %g is outside [0, 1000] DU", opt->sky.ozone_column_du);
                return PARSE_ERROR;
            }
            have_ozone = 1;
            break;
        case OPT_EARTH_SUN_DISTANCE:
            times.distance = 1;
            bad_number = !parse_decimal(arg, &opt->sky.earth_sun_distance_au);
            break;
        case OPT_WAVELENGTH:
            bad_number = !parse_decimal(arg, &d);
            if (!bad_number && d == 0.0) {
                snprintf(msg, msg_size, "--wavelength: 0 is outside [300, 1000] nm");
                return PARSE_ERROR;
            }
            opt->sky.wavelength_nm = d;
            break;
        case OPT_ATMOSPHERE:
            opt->sky.atmosphere_file = arg;
            break;
        case OPT_BIOME:
            opt->sky.biome = arg;
            break;
        case OPT_TURBIDITY:
            bad_number = !parse_decimal(arg, &opt->sky.turbidity);
            break;
        case OPT_AOD550:
            bad_number = !parse_decimal(arg, &d);
            if (!bad_number && d <= 0.0) {
                snprintf(msg, msg_size, "--aod550: %g is outside (0, 10]", d);
                return PARSE_ERROR;
            }
            opt->sky.aod550 = d;
            break;
        case OPT_HUMIDITY:
            bad_number = !parse_decimal(arg, &d);
            if (!bad_number && d < 0.0) {
                snprintf(msg, msg_size, "--humidity: %g is outside [0, 99] %%", d);
                return PARSE_ERROR;
            }
            opt->sky.humidity_percent = d;
            break;
        case OPT_AEROSOL_PHASE:
            if (strcmp(arg, "mie") == 0)
                opt->sky.aerosol_phase = FM_AEROSOL_PHASE_MIE;
            else if (strcmp(arg, "hg") == 0)
                opt->sky.aerosol_phase = FM_AEROSOL_PHASE_HG;
            else {
                snprintf(msg, msg_size, "--aerosol-phase: '%s' is not one of mie, hg", arg);
                return PARSE_ERROR;
            }
            break;
        case OPT_DATE:
            if (!parse_date_arg("--date", arg, &opt->sky.year, &opt->sky.month, &opt->sky.day, msg, msg_size))
                return PARSE_ERROR;
            break;
        case OPT_LATITUDE:
            bad_number = !parse_decimal(arg, &opt->sky.latitude_deg);
            have_latitude = 1;
            break;
        case OPT_LONGITUDE:
            times.longitude = 1;
            bad_number = !parse_decimal(arg, &opt->sky.longitude_deg);
            break;
        case OPT_SAMPLE_SCALE:
            bad_number = !parse_decimal(arg, &opt->render.sample_scale);
            break;
        case OPT_WIDTH:
            if (!parse_whole(arg, -2147483647LL, 2147483647LL, &n)) {
                snprintf(msg, msg_size, "--width: '%s' is not a whole number in [8, 16384]", arg);
                return PARSE_ERROR;
            }
            opt->render.width = (int)n;
            break;
        case OPT_SAMPLES:
            if (!parse_whole(arg, -2147483647LL, 2147483647LL, &n)) {
                snprintf(msg, msg_size, "--samples: '%s' is not a whole number in [1, 16777216]", arg);
                return PARSE_ERROR;
            }
            if (n < 1 || n > 16777216) {
                snprintf(msg, msg_size, "--samples: %lld is outside [1, 16777216]", n);
                return PARSE_ERROR;
            }
            opt->render.reference_samples = (int)n;
            break;
        case OPT_THREADS:
            if (!parse_whole(arg, -2147483647LL, 2147483647LL, &n)) {
                snprintf(msg, msg_size, "--threads: '%s' is not a whole number in [0, 256]", arg);
                return PARSE_ERROR;
            }
            opt->render.threads = (int)n;
            opt->sky.threads = (int)n;
            break;
        case OPT_SEED:
            if (!parse_whole(arg, 0, 9007199254740992LL, &n)) {
                snprintf(msg, msg_size, "--seed: '%s' is not a whole number in [0, 2^53]", arg);
                return PARSE_ERROR;
            }
            opt->render.seed = (uint64_t)n;
            break;
        case OPT_QUALITY:
            if (strcmp(arg, "preview") == 0)
                opt->render.quality = FM_QUALITY_PREVIEW;
            else if (strcmp(arg, "final") == 0)
                opt->render.quality = FM_QUALITY_FINAL;
            else if (strcmp(arg, "reference") == 0)
                opt->render.quality = FM_QUALITY_REFERENCE;
            else {
                snprintf(msg, msg_size, "--quality: '%s' is not one of preview, final, reference", arg);
                return PARSE_ERROR;
            }
            break;
        case OPT_PROGRESS:
            if (strcmp(arg, "tty") == 0)
                opt->progress = PROGRESS_TTY;
            else if (strcmp(arg, "json") == 0)
                opt->progress = PROGRESS_JSON;
            else if (strcmp(arg, "none") == 0)
                opt->progress = PROGRESS_NONE;
            else {
                snprintf(msg, msg_size, "--progress: '%s' is not one of tty, json, none", arg);
                return PARSE_ERROR;
            }
            break;
        case OPT_NO_SUN_DISK:
            opt->render.sun_disk = 0;
            break;
        case OPT_SIDECAR:
            opt->sidecar = arg;
            break;
        case OPT_COLORSPACE:
            opt->colorspace = arg;
            break;
        case OPT_LIST_COLORSPACES:
            opt->list_colorspaces = 1;
            break;
        case OPT_PREVIEW:
            opt->preview = arg;
            break;
        case OPT_HALF:
            opt->half = 1;
            break;
        case OPT_SUN_DISK_MAP:
            opt->sun_disk_map = arg;
            break;
        case OPT_SPECTRAL:
            opt->spectral = arg;
            opt->render.spectral = 1;
            break;
        case OPT_COMPRESSION:
            if (strcmp(arg, "zip") == 0)
                opt->compression = FM_EXR_ZIP;
            else if (strcmp(arg, "piz") == 0)
                opt->compression = FM_EXR_PIZ;
            else if (strcmp(arg, "dwaa") == 0)
                opt->compression = FM_EXR_DWAA;
            else {
                snprintf(msg, msg_size, "--compression: unknown method '%s' (known: zip, piz, dwaa)", arg);
                return PARSE_ERROR;
            }
            break;
        case OPT_EXPOSURE:
            opt->have_exposure = 1;
            bad_number = !parse_decimal(arg, &opt->exposure_ev);
            if (!bad_number && !(fabs(opt->exposure_ev) <= 100.0)) {
                snprintf(msg, msg_size, "--exposure: %s is out of range [-100, 100]", arg);
                return PARSE_ERROR;
            }
            break;
        case OPT_TIME:
        case OPT_UTC_OFFSET:
        case OPT_REFRACTION:
        case OPT_PRESSURE:
        case OPT_TEMPERATURE:
        case OPT_DELTA_T:
        case OPT_TIME_START:
        case OPT_TIME_END:
        case OPT_STEP:
            if (!parse_time_option(c, name, arg, opt, &times, msg, msg_size))
                return PARSE_ERROR;
            break;
        case ':':
            snprintf(msg, msg_size, "%s needs a value", argv[optind - 1]);
            return PARSE_ERROR;
        case '?':
        default:
            if (optopt >= 256 && strchr(argv[optind - 1], '='))
                snprintf(msg, msg_size, "%.*s takes no value", (int)strcspn(argv[optind - 1], "="), argv[optind - 1]);
            else if (optopt && optopt < 256)
                snprintf(msg, msg_size, "unknown option '-%c' (firmament --help lists the options)", optopt);
            else
                snprintf(msg, msg_size, "unknown option '%s' (firmament --help lists the options)", argv[optind - 1]);
            return PARSE_ERROR;
        }
        if (c == OPT_BIOME || c == OPT_TURBIDITY || c == OPT_AOD550 || c == OPT_HUMIDITY || c == OPT_AEROSOL_PHASE ||
            c == OPT_OZONE)
            builtin_only = name;
        if (bad_number) {
            snprintf(msg, msg_size, "--%s: '%s' is not a number", name ? name : "?", arg);
            return PARSE_ERROR;
        }
        index = -1;
    }
    if (optind < argc) {
        snprintf(msg, msg_size, "unexpected argument '%s' (options start with --)", argv[optind]);
        return PARSE_ERROR;
    }
    if (!finish_time_options(opt, &times, have_latitude, msg, msg_size))
        return PARSE_ERROR;
    if ((have_latitude || times.longitude) && opt->sky.year == 0) {
        /* the place chooses the sun (with --time) and the ozone (with --date); alone it does nothing */
        snprintf(msg, msg_size, "--%s: applies only with --date (the ozone climatology) or --time (the sun)",
                 have_latitude ? "latitude" : "longitude");
        return PARSE_ERROR;
    }
    if (opt->render.reference_samples > 0 && opt->render.quality != FM_QUALITY_REFERENCE) {
        snprintf(msg, msg_size, "--samples: applies only with --quality reference");
        return PARSE_ERROR;
    }
    if (opt->sky.atmosphere_file && !builtin_only && opt->sky.year != 0 && opt->sky.hour == FM_NO_TIME)
        builtin_only = "date"; /* without a time, the date is for the ozone climatology only */
    if (camera_specific && opt->render.camera.type != camera_needed) {
        snprintf(msg, msg_size, "--%s: applies only to --camera %s", camera_specific,
                 camera_needed == FM_CAMERA_FISHEYE ? "fisheye" : "pinhole");
        return PARSE_ERROR;
    }
    if (opt->sky.atmosphere_file && builtin_only) {
        snprintf(msg, msg_size, "--%s: does not apply with --atmosphere (the file defines every constituent)",
                 builtin_only);
        return PARSE_ERROR;
    }
    if (opt->sky.year != 0 && !have_ozone && !opt->sky.atmosphere_file) {
        /* a date and a place choose the ozone column, unless --ozone-du says otherwise */
        if (!have_latitude) {
            snprintf(msg, msg_size, "--date: the ozone climatology also needs --latitude (or give --ozone-du)");
            return PARSE_ERROR;
        }
        opt->sky.ozone_column_du = FM_OZONE_FROM_CLIMATOLOGY;
    }
    if (opt->preview && opt->sky.wavelength_nm > 0.0) {
        snprintf(msg, msg_size, "--preview: needs a colour render (not --wavelength)");
        return PARSE_ERROR;
    }
    if (opt->spectral && (opt->sky.wavelength_nm > 0.0 || opt->frames > 0)) {
        snprintf(msg, msg_size, "--spectral: needs a single colour render (not --wavelength nor a time series)");
        return PARSE_ERROR;
    }
    if (opt->sun_disk_map && (!opt->render.sun_disk || opt->frames > 0 || opt->spectral ||
                              opt->sky.wavelength_nm > 0.0 || opt->render.camera.type != FM_CAMERA_EQUIRECT)) {
        snprintf(msg, msg_size, "--sun-disk-map: needs a single colour equirect render with the disk (not "
                                "--no-sun-disk, a time series, --spectral or --wavelength)");
        return PARSE_ERROR;
    }
    if (opt->have_exposure && !opt->preview) {
        snprintf(msg, msg_size, "--exposure: applies to --preview only");
        return PARSE_ERROR;
    }
    return PARSE_RUN;
}

#include "args.h"

#include <errno.h>
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
          "       firmament compare IMAGE.exr REFERENCE.exr [--exclude-sun DEG] [--json]\n"
          "       firmament --help | --version\n"
          "\n"
          "Renders the sky seen from one place as an equirectangular OpenEXR map (Blender's\n"
          "Environment Texture layout: north at u = 0.25, east at the centre, zenith at the top) and a\n"
          "JSON sidecar with the sun's direction and light.  Values are CIE-weighted radiance in\n"
          "linear Rec.709 (Y x 683 = cd/m^2), or spectral radiance with --wavelength.\n"
          "\n"
          "Sky:\n"
          "  --sun-elevation DEG    elevation of the sun's centre, [-90, 90] (default 30)\n"
          "  --sun-azimuth DEG      from north toward east, [-360, 360] (default 180, south)\n"
          "  --altitude M           observer above the ground, [0, 20000] (default 0)\n"
          "  --albedo X             Lambertian ground reflectance, [0, 1] (default 0.2)\n"
          "  --ozone-du X           total ozone column in Dobson units, [0, 1000]; 0 disables (default:\n"
          "                         from the climatology with --date, else 300)\n"
          "  --date YYYY-MM-DD      date (1900-2100) for the ozone climatology; needs --latitude\n"
          "  --latitude DEG         [-90, 90], north positive\n"
          "  --longitude DEG        [-180, 180], east positive (default 0)\n"
          "Aerosols:\n"
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
          "  --width W              even, [8, 16384]; height = W/2 (default 2048)\n"
          "  --no-sun-disk          leave the sun disk out of the map (its aureole stays)\n"
          "Quality:\n"
          "  --quality LEVEL        preview | final | reference (default final)\n"
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

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

static int parse_long(const char *s, long long lo, long long hi, long long *out)
{
    char *end;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

parse_result options_parse(int argc, char **argv, options *opt, char *msg, size_t msg_size)
{
    opt->sky = fm_sky_params_default();
    opt->render = fm_render_params_default();
    opt->output = "sky.exr";
    opt->sidecar = NULL;
    opt->progress = PROGRESS_AUTO;

    opterr = 0; /* we print our own, one-line messages */
    optind = 1;
    int c, index = -1, have_ozone = 0, have_latitude = 0;
    const char *builtin_only = NULL; /* an option about the built-in atmosphere that was given */
    while ((c = getopt_long(argc, argv, ":o:h", long_options, &index)) != -1) {
        const char *name = index >= 0 ? long_options[index].name : NULL;
        const char *arg = optarg;
        double d = 0.0;
        long long n = 0;
        int bad_number = 0;
        switch (c) {
        case 'o':
            opt->output = arg;
            break;
        case 'h':
            options_print_usage();
            return PARSE_EXIT_OK;
        case OPT_SUN_ELEVATION:
            bad_number = !parse_double(arg, &opt->sky.sun_elevation_deg);
            break;
        case OPT_SUN_AZIMUTH:
            bad_number = !parse_double(arg, &opt->sky.sun_azimuth_deg);
            break;
        case OPT_ALTITUDE:
            bad_number = !parse_double(arg, &opt->sky.observer_altitude_m);
            break;
        case OPT_ALBEDO:
            bad_number = !parse_double(arg, &opt->sky.ground_albedo);
            break;
        case OPT_OZONE:
            bad_number = !parse_double(arg, &opt->sky.ozone_column_du);
            if (!bad_number && opt->sky.ozone_column_du < 0.0) { /* negative values are library sentinels */
                snprintf(msg, msg_size, "--ozone-du: %g is outside [0, 1000] DU", opt->sky.ozone_column_du);
                return PARSE_ERROR;
            }
            have_ozone = 1;
            break;
        case OPT_EARTH_SUN_DISTANCE:
            bad_number = !parse_double(arg, &opt->sky.earth_sun_distance_au);
            break;
        case OPT_WAVELENGTH:
            bad_number = !parse_double(arg, &d);
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
            bad_number = !parse_double(arg, &opt->sky.turbidity);
            break;
        case OPT_AOD550:
            bad_number = !parse_double(arg, &d);
            if (!bad_number && d <= 0.0) {
                snprintf(msg, msg_size, "--aod550: %g is outside (0, 10]", d);
                return PARSE_ERROR;
            }
            opt->sky.aod550 = d;
            break;
        case OPT_HUMIDITY:
            bad_number = !parse_double(arg, &d);
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
        case OPT_DATE: {
            int y, m, dd, used = 0;
            if (sscanf(arg, "%4d-%2d-%2d%n", &y, &m, &dd, &used) != 3 || used != 10 || arg[used] != '\0') {
                snprintf(msg, msg_size, "--date: '%s' is not a date YYYY-MM-DD", arg);
                return PARSE_ERROR;
            }
            opt->sky.year = y;
            opt->sky.month = m;
            opt->sky.day = dd;
            break;
        }
        case OPT_LATITUDE:
            bad_number = !parse_double(arg, &opt->sky.latitude_deg);
            have_latitude = 1;
            break;
        case OPT_LONGITUDE:
            bad_number = !parse_double(arg, &opt->sky.longitude_deg);
            break;
        case OPT_SAMPLE_SCALE:
            bad_number = !parse_double(arg, &opt->render.sample_scale);
            break;
        case OPT_WIDTH:
            if (!parse_long(arg, -2147483647LL, 2147483647LL, &n)) {
                snprintf(msg, msg_size, "--width: '%s' is not a whole number", arg);
                return PARSE_ERROR;
            }
            opt->render.width = (int)n;
            break;
        case OPT_SAMPLES:
            if (!parse_long(arg, -2147483647LL, 2147483647LL, &n)) {
                snprintf(msg, msg_size, "--samples: '%s' is not a whole number", arg);
                return PARSE_ERROR;
            }
            if (n < 1) {
                snprintf(msg, msg_size, "--samples: %lld is outside [1, 16777216]", n);
                return PARSE_ERROR;
            }
            opt->render.reference_samples = (int)n;
            break;
        case OPT_THREADS:
            if (!parse_long(arg, -2147483647LL, 2147483647LL, &n)) {
                snprintf(msg, msg_size, "--threads: '%s' is not a whole number", arg);
                return PARSE_ERROR;
            }
            opt->render.threads = (int)n;
            opt->sky.threads = (int)n;
            break;
        case OPT_SEED:
            if (!parse_long(arg, 0, 9007199254740992LL, &n)) {
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
        case ':':
            snprintf(msg, msg_size, "%s needs a value", argv[optind - 1]);
            return PARSE_ERROR;
        case '?':
        default:
            if (optopt && optopt < 256)
                snprintf(msg, msg_size, "unknown option '-%c' (firmament --help lists the options)", optopt);
            else
                snprintf(msg, msg_size, "unknown option '%s' (firmament --help lists the options)", argv[optind - 1]);
            return PARSE_ERROR;
        }
        if (c == OPT_BIOME || c == OPT_TURBIDITY || c == OPT_AOD550 || c == OPT_HUMIDITY || c == OPT_AEROSOL_PHASE ||
            c == OPT_OZONE || c == OPT_DATE)
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
    return PARSE_RUN;
}

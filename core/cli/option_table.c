#include "option_table.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#define AT(member) offsetof(options, member)
#define NO_RANGE {NULL, 0.0, 0.0, 0, NULL}

static const option_word quality_words[] = {
    {"preview", FM_QUALITY_PREVIEW}, {"final", FM_QUALITY_FINAL}, {"reference", FM_QUALITY_REFERENCE}, {NULL, 0}};
static const option_word phase_words[] = {{"mie", FM_AEROSOL_PHASE_MIE}, {"hg", FM_AEROSOL_PHASE_HG}, {NULL, 0}};
static const option_word on_off_words[] = {{"on", 1}, {"off", 0}, {NULL, 0}};
static const option_word camera_words[] = {
    {"equirect", FM_CAMERA_EQUIRECT}, {"fisheye", FM_CAMERA_FISHEYE}, {"pinhole", FM_CAMERA_PINHOLE}, {NULL, 0}};
static const option_word projection_words[] = {
    {"equidistant", FM_FISHEYE_EQUIDISTANT}, {"equisolid", FM_FISHEYE_EQUISOLID}, {NULL, 0}};
static const option_word compression_words[] = {
    {"zip", FM_EXR_ZIP}, {"piz", FM_EXR_PIZ}, {"dwaa", FM_EXR_DWAA}, {NULL, 0}};
static const option_word file_format_words[] = {{"exr", FORMAT_EXR}, {"hdr", FORMAT_HDR}, {NULL, 0}};
static const option_word progress_words[] = {
    {"tty", PROGRESS_TTY}, {"json", PROGRESS_JSON}, {"none", PROGRESS_NONE}, {NULL, 0}};

static const char SKY[] = "Sky";
static const char SUN[] = "Sun from the date and time (NREL SPA, +-0.0003 deg)";
static const char AEROSOLS[] = "Aerosols";
static const char CLOUDS[] = "Clouds (horizontally uniform layers, docs/clouds.md)";
static const char IMAGE[] = "Image";
static const char CAMERA[] = "Camera";
static const char COLOUR[] = "Colour (OpenColorIO; config $OCIO, else firmament's presets/ocio/config.ocio)";
static const char QUALITY[] = "Quality";
static const char OTHER[] = "Other";

const option_spec option_specs[] = {
    {"sun-elevation", 0, "DEG", OPTION_NUMBER, AT(sky.sun_elevation_deg), "sun_elevation_deg", NO_RANGE, NULL, 0,
     FROM_TIME, SKY, "elevation of the sun's centre, %R", NULL},
    {"sun-azimuth", 0, "DEG", OPTION_NUMBER, AT(sky.sun_azimuth_deg), "sun_azimuth_deg", NO_RANGE, NULL, 0, FROM_TIME,
     SKY, "from north toward east, %R", "180, south"},
    {"altitude", 0, "M", OPTION_NUMBER, AT(sky.observer_altitude_m), "observer_altitude_m", NO_RANGE, NULL, 0, 0, SKY,
     "observer above the ground, %R: rooftops, mountains, aircraft", NULL},
    {"albedo", 0, "X", OPTION_NUMBER, AT(sky.ground_albedo), "ground_albedo", NO_RANGE, NULL, 0, 0, SKY,
     "Lambertian ground reflectance, %R", NULL},
    {"ozone-du", 0, "X", OPTION_NUMBER, AT(sky.ozone_column_du), "ozone_column_du", NO_RANGE, NULL, 0, NEEDS_BUILTIN,
     SKY, "total ozone column, %R; 0 disables ozone", "from the climatology with --date, else 300"},
    {"earth-sun-distance", 0, "AU", OPTION_NUMBER, AT(sky.earth_sun_distance_au), "earth_sun_distance_au", NO_RANGE,
     NULL, 0, 0, SKY, "%R: solar irradiance scales as 1/d^2, the disk as 1/d",
     "the date's (at 12:00 UT), 1 without --date"},
    {"date", 0, "YYYY-MM-DD", OPTION_DATE, AT(sky.year), "date", NO_RANGE, NULL, 0, 0, SKY,
     "date (1900-2100) for the ozone climatology, the ozone profile's season and the Earth-Sun distance, and with "
     "--time for the sun; needs --latitude",
     NULL},
    {"latitude", 0, "DEG", OPTION_NUMBER, AT(sky.latitude_deg), "latitude_deg", NO_RANGE, NULL, 0, 0, SKY,
     "%R, north positive; with --date alone it chooses the ozone column, without --date it is refused", NULL},
    {"longitude", 0, "DEG", OPTION_NUMBER, AT(sky.longitude_deg), "longitude_deg", NO_RANGE, NULL, 0, 0, SKY,
     "%R, east positive; needed with --time", NULL},
    {"wavelength", 0, "NM", OPTION_NUMBER, AT(sky.wavelength_nm), "wavelength_nm", NO_RANGE, NULL, 0, 0, SKY,
     "monochromatic render at one wavelength, %R: one channel Y of spectral radiance in W m^-2 sr^-1 nm^-1",
     "a colour render"},
    {"atmosphere", 0, "FILE", OPTION_TEXT, AT(sky.atmosphere_file), "atmosphere_file", NO_RANGE, NULL, 0, 0, SKY,
     "a custom atmosphere (JSON, docs/atmosphere-file.md) instead of the built-in Earth: its planet, constituents "
     "and optionally its ground albedo (over --albedo) and solar spectrum; the options of the built-in ozone and "
     "aerosols are refused with it; e.g. presets/atmospheres/reference-rayleigh.json",
     "the built-in Earth"},

    {"time", 0, "HH:MM[:SS]", OPTION_TIME, 0, "time", NO_RANGE, NULL, 0, 0, SUN,
     "local clock time on --date at --latitude, --longitude: sets the sun's apparent elevation and azimuth, unless "
     "--sun-elevation or --sun-azimuth are given",
     NULL},
    {"utc-offset", 0, "+-HH[:MM]", OPTION_OFFSET, AT(sky.utc_offset_min), "utc_offset_min", NO_RANGE, NULL, 0,
     NEEDS_TIME, SUN, "local time minus UTC, -12:00 to +14:00", "+00:00"},
    {"refraction", 0, "on|off", OPTION_CHOICE, AT(sky.refraction), "refraction", NO_RANGE, on_off_words, 0,
     NEEDS_TIME, SUN, "atmospheric refraction lifts the sun (the disk stays round)", NULL},
    {"pressure", 0, "MBAR", OPTION_NUMBER, AT(sky.pressure_mbar), "pressure_mbar", NO_RANGE, NULL, 0, NEEDS_TIME,
     SUN, "air pressure for refraction, %R", NULL},
    {"temperature", 0, "C", OPTION_NUMBER, AT(sky.temperature_c), "temperature_c", NO_RANGE, NULL, 0, NEEDS_TIME, SUN,
     "air temperature for refraction, %R", NULL},
    {"delta-t", 0, "S", OPTION_NUMBER, AT(sky.delta_t_s), "delta_t_s", NO_RANGE, NULL, 0, NEEDS_TIME, SUN,
     "TT - UT, %R", "the Espenak & Meeus estimate for the date"},
    {"time-start", 0, "HH:MM[:SS]", OPTION_TIME, 0, NULL, NO_RANGE, NULL, 0, 0, SUN,
     "a time series instead of --time, with --time-end and --step: one map every --step minutes from start to end "
     "(inclusive, on --date, at most 10000), OUT_0000.exr, OUT_0001.exr, ... each with its sidecar (a --sidecar "
     "path is numbered the same way); the atmosphere's tables are built once",
     NULL},
    {"time-end", 0, "HH:MM[:SS]", OPTION_TIME, 0, NULL, NO_RANGE, NULL, 0, 0, SUN,
     "the series' last time (inclusive, not before --time-start)", NULL},
    {"step", 0, "MIN", OPTION_NUMBER, AT(step_min), NULL, {NULL, 0.0, 1440.0, 1, "min"}, NULL, 0, 0, SUN,
     "minutes between the series' maps, %R", NULL},

    {"biome", 0, "NAME", OPTION_TEXT, AT(sky.biome), "biome", NO_RANGE, NULL, 0, NEEDS_BUILTIN | BIOME_WORDS,
     AEROSOLS, "aerosol environment: %W (presets/biomes/), or a biome JSON file", NULL},
    {"turbidity", 0, "X", OPTION_NUMBER, AT(sky.turbidity), "turbidity", NO_RANGE, NULL, 0, NEEDS_BUILTIN, AEROSOLS,
     "multiplier of the biome's aerosol number density, %R; 0 = no aerosol", NULL},
    {"aod550", 0, "X", OPTION_NUMBER, AT(sky.aod550), "aod550", NO_RANGE, NULL, 0, NEEDS_BUILTIN, AEROSOLS,
     "instead of --turbidity (not with it): scale the biome to this aerosol optical depth at 550 nm, %R",
     NULL},
    {"humidity", 0, "RH", OPTION_NUMBER, AT(sky.humidity_percent), "humidity_percent", NO_RANGE, NULL, 0,
     NEEDS_BUILTIN, AEROSOLS,
     "relative humidity, %R: hygroscopic growth of water-soluble, sea-salt and sulfate particles", "the biome's"},
    {"print-atmosphere", 0, NULL, OPTION_SWITCH, AT(print_atmosphere), NULL, NO_RANGE, NULL, 1, 0, AEROSOLS,
     "print the sidecar's \"atmosphere\" (optical depths, visibility) as JSON and exit, without rendering", NULL},
    {"aerosol-phase", 0, "MODEL", OPTION_CHOICE, AT(sky.aerosol_phase), "aerosol_phase", NO_RANGE, phase_words, 0,
     NEEDS_BUILTIN, AEROSOLS,
     "mie (the tabulated Mie phase function, sampled exactly) | hg (Henyey-Greenstein with the Mie asymmetry "
     "parameter)",
     NULL},

    {"cloud", 0, "LIST", OPTION_TEXT, AT(sky.clouds), "clouds", NO_RANGE, NULL, 0, CLOUD_WORDS, CLOUDS,
     "cloud layers, comma-separated (at most 4, e.g. cirrostratus,altostratus): %W (presets/clouds/), or cloud "
     "JSON files; with the built-in or an --atmosphere file's sky",
     "none"},
    {"cloud-tau", 0, "X", OPTION_NUMBER, AT(sky.cloud_tau550), "cloud_tau550", NO_RANGE, NULL, 0, 0, CLOUDS,
     "optical depth at 550 nm of the first --cloud layer, %R", "its file's"},
    {"cloud-lwp", 0, "G", OPTION_NUMBER, AT(sky.cloud_lwp_gm2), "cloud_lwp_gm2", NO_RANGE, NULL, 0, 0, CLOUDS,
     "instead of --cloud-tau: liquid water path of the first (water) --cloud layer, %R", "its file's"},
    {"cloud-base", 0, "KM", OPTION_NUMBER, AT(sky.cloud_base_km), "cloud_base_km", NO_RANGE, NULL, 0, 0, CLOUDS,
     "base of the first --cloud layer above the ground, %R", "its file's"},
    {"cloud-thickness", 0, "KM", OPTION_NUMBER, AT(sky.cloud_thickness_km), "cloud_thickness_km", NO_RANGE, NULL, 0, 0,
     CLOUDS, "thickness of the first --cloud layer, %R", "its file's"},
    {"fog-visibility", 0, "M", OPTION_NUMBER, AT(sky.fog_visibility_m), "fog_visibility_m", NO_RANGE, NULL, 0, 0,
     CLOUDS,
     "a fog layer on the ground (presets/clouds/fog.json, or the listed fog) of this visibility, %R: extinction "
     "3.912 / M at 550 nm (Koschmieder)",
     "no fog"},

    {"output", 'o', "FILE", OPTION_TEXT, AT(output), NULL, NO_RANGE, NULL, 0, FILE_ARG, IMAGE,
     "output EXR; the sidecar is FILE with its extension replaced by .json", NULL},
    {"sidecar", 0, "FILE", OPTION_TEXT, AT(sidecar), NULL, NO_RANGE, NULL, 0, FILE_ARG, IMAGE,
     "sidecar path instead of the default", "FILE with .json"},
    {"width", 0, "W", OPTION_WHOLE, AT(render.width), "width", NO_RANGE, NULL, 0, 0, IMAGE,
     "even, %R; height = W/2 for equirect, W for fisheye, W/aspect for pinhole", NULL},
    {"no-sun-disk", 0, NULL, OPTION_SWITCH, AT(render.sun_disk), "sun_disk", NO_RANGE, NULL, 0, 0, IMAGE,
     "leave the sun disk out of the map (its aureole stays)", "the disk in"},
    {"sun-disk-map", 0, "FILE", OPTION_TEXT, AT(sun_disk_map), NULL, NO_RANGE, NULL, 0, FILE_ARG, IMAGE,
     "also write FILE (an EXR, and its sidecar) with the disk, and leave the disk out of the main map: one "
     "render, sky for lighting and disk for the camera; equirect colour renders only, not with a time series, "
     "--spectral or --no-sun-disk",
     NULL},
    {"preset", 0, "NAME|FILE", OPTION_TEXT, 0, "preset", NO_RANGE, NULL, 0, NOT_PARSED, IMAGE,
     "a sky preset (presets/skies/NAME.json or a JSON file): its settings apply as if given first, so options "
     "given on the command line override them",
     NULL},
    {"half", 0, NULL, OPTION_SWITCH, AT(half), "half", NO_RANGE, NULL, 1, 0, IMAGE,
     "16-bit half-float EXR; refused (exit 2, nothing written) when a value exceeds 65504, as the sun disk does: "
     "add --no-sun-disk",
     "32-bit float"},
    {"compression", 0, "METHOD", OPTION_CHOICE, AT(compression), "compression", NO_RANGE, compression_words, 0, 0,
     IMAGE,
     "zip | piz (lossless; PIZ a quarter smaller than ZIP on skies, and faster) | dwaa (lossy, half precision, "
     "level 45; not with the sun disk beyond 65504)",
     NULL},
    {"format", 0, "FORMAT", OPTION_CHOICE, AT(format), NULL, NO_RANGE, file_format_words, 0, 0, IMAGE,
     "exr | hdr: a Radiance RGBE picture, the EXR's values (luminance = 683 x Y cd/m^2; x 683/179 = 3.816 for "
     "Radiance's 179 lm/W), the sky's parameters as header comments; not with --half or --compression",
     "hdr for an -o name ending .hdr, else exr"},
    {"spectral", 0, "FILE.exr", OPTION_TEXT, AT(spectral), "spectral", NO_RANGE, NULL, 0, FILE_ARG, IMAGE,
     "also write the spectral radiance (41 wavelengths, 380-780 nm) in the spectral OpenEXR layout of Fichet et "
     "al. 2021 (41 x the image memory); not with --wavelength or a time series",
     NULL},

    {"camera", 0, "TYPE", OPTION_CHOICE, AT(render.camera.type), "camera.type", NO_RANGE, camera_words, 0, 0, CAMERA,
     "%W", NULL},
    {"fisheye-projection", 0, "P", OPTION_CHOICE, AT(render.camera.fisheye_projection), "camera.fisheye_projection",
     NO_RANGE, projection_words, 0, NEEDS_FISHEYE, CAMERA,
     "fisheye: equidistant (r ~ zenith angle) | equisolid (r ~ 2 sin(zenith angle / 2), equal-area); upward "
     "hemisphere in the inscribed circle, zenith at the centre, north up and east LEFT as seen looking up; pixels "
     "outside the circle are 0",
     NULL},
    {"fov", 0, "DEG", OPTION_NUMBER, AT(render.camera.fov_deg), "camera.fov_deg", NO_RANGE, NULL, 0, NEEDS_PINHOLE,
     CAMERA, "pinhole: horizontal field of view, %R", NULL},
    {"look-azimuth", 0, "DEG", OPTION_NUMBER, AT(render.camera.look_azimuth_deg), "camera.look_azimuth_deg", NO_RANGE,
     NULL, 0, NEEDS_PINHOLE, CAMERA, "pinhole: view direction from north toward east, %R", "180, south"},
    {"look-elevation", 0, "DEG", OPTION_NUMBER, AT(render.camera.look_elevation_deg), "camera.look_elevation_deg",
     NO_RANGE, NULL, 0, NEEDS_PINHOLE, CAMERA, "pinhole: view direction above the horizontal, %R; level horizon, no roll",
     NULL},
    {"aspect", 0, "W:H|X", OPTION_RATIO, AT(render.camera.aspect), "camera.aspect", NO_RANGE, NULL, 0, NEEDS_PINHOLE,
     CAMERA, "pinhole: width / height, e.g. 16:9 or 1.5; height = W/aspect rounded to even, within --width's range",
     "16:9"},

    {"colorspace", 0, "NAME", OPTION_TEXT, AT(colorspace), NULL, NO_RANGE, NULL, 0, 0, COLOUR,
     "scene-linear colour space of the EXR and of the sidecar's RGB values, any of the config's (e.g. ACEScg)", NULL},
    {"list-colorspaces", 0, NULL, OPTION_SWITCH, AT(list_colorspaces), NULL, NO_RANGE, NULL, 1, 0, COLOUR,
     "print the config's colour spaces and exit", NULL},
    {"preview", 0, "FILE.png", OPTION_TEXT, AT(preview), NULL, NO_RANGE, NULL, 0, FILE_ARG, COLOUR,
     "also write an 8-bit sRGB preview (display \"sRGB\", view \"Standard\"); in a series, numbered like the EXR",
     NULL},
    {"exposure", 0, "EV", OPTION_NUMBER, AT(exposure_ev), NULL, {NULL, -100.0, 100.0, 0, "EV"}, NULL, 0, 0, COLOUR,
     "preview exposure: values x 2^EV before the display transform, %R",
     "the sky's log-average luminance above the horizon -> 0.18"},

    {"quality", 0, "LEVEL", OPTION_CHOICE, AT(render.quality), "quality", NO_RANGE, quality_words, 0, 0, QUALITY,
     "%W; final takes up to 2x its paths in deep twilight (sun -11 to -21 deg, most at -18)", NULL},
    {"samples", 0, "N", OPTION_WHOLE, AT(render.reference_samples), "reference_samples", NO_RANGE, NULL, 0, 0, QUALITY,
     "reference quality only: paths per pixel, %R (slow by design, about 3 us of one core per colour path)", "256"},
    {"sample-scale", 0, "X", OPTION_NUMBER, AT(render.sample_scale), "sample_scale", NO_RANGE, NULL, 0, 0, QUALITY,
     "multiply every sample count of the quality level, %R", NULL},
    {"seed", 0, "N", OPTION_SEED, AT(render.seed), "seed", {NULL, 0.0, 9007199254740992.0, 0, ""}, NULL, 0, 0,
     QUALITY, "random seed, %R: the same seed gives the same bits for any thread count", NULL},
    {"threads", 0, "N", OPTION_WHOLE, AT(render.threads), "threads", NO_RANGE, NULL, 0, 0, QUALITY,
     "worker threads, %R; 0 = all cores", NULL},
    {"progress", 0, "MODE", OPTION_CHOICE, AT(progress), NULL, NO_RANGE, progress_words, 0, 0, QUALITY,
     "tty (a bar on stderr) | json (lines on stdout) | none", "tty when stderr is a terminal, else none"},
    {"help", 'h', NULL, OPTION_SWITCH, 0, NULL, NO_RANGE, NULL, 0, NOT_PARSED, OTHER, "print this and exit", NULL},
};
const int option_count = (int)(sizeof option_specs / sizeof option_specs[0]);

const option_spec *option_find(const char *flag)
{
    if (strncmp(flag, "--", 2) == 0)
        flag += 2;
    for (int i = 0; i < option_count; i++)
        if (strcmp(option_specs[i].flag, flag) == 0)
            return &option_specs[i];
    return NULL;
}

const option_spec *option_for_field(const char *field)
{
    for (int i = 0; i < option_count; i++)
        if (option_specs[i].field && strcmp(option_specs[i].field, field) == 0)
            return &option_specs[i];
    /* the library's name for the sky's time of day */
    return strcmp(field, "hour") == 0 ? option_find("time") : NULL;
}

const fm_param_range *option_range(const option_spec *o)
{
    if (o->own_range.unit)
        return &o->own_range;
    return o->field ? fm_param_range_of(o->field) : NULL;
}

static void format_bound(double v, char *out, size_t size)
{
    if (v == 9007199254740992.0)
        snprintf(out, size, "2^53");
    else
        snprintf(out, size, "%.10g", v);
}

void option_format_range(const fm_param_range *r, char *out, size_t size)
{
    char lo[32], hi[32];
    format_bound(r->min, lo, sizeof lo);
    format_bound(r->max, hi, sizeof hi);
    snprintf(out, size, "%c%s, %s]%s%s", r->min_open ? '(' : '[', lo, hi, r->unit[0] ? " " : "", r->unit);
}

/* ---- the usage --------------------------------------------------------------------------------- */

/* "none | background | ... | urban" (biomes) or "altostratus | ... | stratus" (clouds), each looked
 * up once.  Names that cannot be listed leave "none" (or nothing) alone and say why on stderr, at the
 * first call: the usage and the JSON make them before writing their first line, so that the warning
 * never lands inside them (never the words of the message as choices). */
static const char *preset_words(int biomes)
{
    static char words[2][800];
    static int ready[2];
    char *out = words[biomes];
    if (ready[biomes])
        return out;
    ready[biomes] = 1;
    char names[700];
    fm_error err;
    fm_status s = biomes ? fm_biome_names(NULL, names, sizeof names, &err) : fm_cloud_names(NULL, names, sizeof names, &err);
    if (s != FM_OK) {
        names[0] = '\0';
        fprintf(stderr, "firmament: warning: %s: %s\n", biomes ? "--biome lists no biomes" : "--cloud lists no clouds",
                err.message);
    }
    size_t used = (size_t)snprintf(out, sizeof words[0], "%s", biomes ? "none" : "");
    for (char *w = strtok(names, ", "); w && used < sizeof words[0]; w = strtok(NULL, ", "))
        used += (size_t)snprintf(out + used, sizeof words[0] - used, "%s%s", used ? " | " : "", w);
    return out;
}

/* The biomes' or clouds' words, or the row's. */
static void format_words(const option_spec *o, char *out, size_t size)
{
    out[0] = '\0';
    if (o->flags & (BIOME_WORDS | CLOUD_WORDS)) {
        snprintf(out, size, "%s", preset_words((o->flags & BIOME_WORDS) != 0));
        return;
    }
    size_t used = 0;
    for (const option_word *w = o->words; w && w->word && used < size; w++)
        used += (size_t)snprintf(out + used, size - used, "%s%s", w == o->words ? "" : " | ", w->word);
}

/* The default as the usage writes it, or "" when there is none to show. */
static void format_default(const option_spec *o, char *out, size_t size)
{
    static options defaults;
    static int ready;
    if (!ready) {
        options_set_defaults(&defaults);
        ready = 1;
    }
    const char *at = (const char *)&defaults + o->offset;
    const fm_param_range *r = option_range(o);
    out[0] = '\0';
    if (o->default_text) {
        snprintf(out, size, "%s", o->default_text);
    } else if (o->kind == OPTION_NUMBER) {
        double v;
        memcpy(&v, at, sizeof v);
        if (r && (r->min_open ? v > r->min : v >= r->min) && v <= r->max)
            snprintf(out, size, "%g", v);
    } else if (o->kind == OPTION_WHOLE) {
        int v;
        memcpy(&v, at, sizeof v);
        snprintf(out, size, "%d", v);
    } else if (o->kind == OPTION_SEED) {
        uint64_t v;
        memcpy(&v, at, sizeof v);
        snprintf(out, size, "%llu", (unsigned long long)v);
    } else if (o->kind == OPTION_CHOICE) {
        int v;
        memcpy(&v, at, sizeof v);
        for (const option_word *w = o->words; w->word; w++)
            if (w->value == v)
                snprintf(out, size, "%s", w->word);
    } else if (o->kind == OPTION_TEXT && o->offset) {
        const char *s;
        memcpy(&s, at, sizeof s);
        if (s)
            snprintf(out, size, "%s", s);
    }
}

/* The help with %R and %W filled in, and the default after it when with_default. */
static void describe(const option_spec *o, int with_default, char *out, size_t size)
{
    char range[64] = "", words[800] = "", def[128];
    const fm_param_range *r = option_range(o);
    if (r)
        option_format_range(r, range, sizeof range);
    format_words(o, words, sizeof words);
    size_t used = 0;
    for (const char *c = o->help; *c && used + 1 < size; c++) {
        if (c[0] == '%' && (c[1] == 'R' || c[1] == 'W')) {
            used += (size_t)snprintf(out + used, size - used, "%s", c[1] == 'R' ? range : words);
            c++;
        } else {
            out[used++] = *c;
        }
    }
    out[used < size ? used : size - 1] = '\0';
    format_default(o, def, sizeof def);
    if (with_default && def[0] && used < size)
        snprintf(out + used, size - used, " (default %s)", def);
}

/* Writes text wrapped before column 100, the cursor being at `column`; the lines after the first
 * start at `indent`. */
static void print_wrapped(FILE *f, const char *text, int column, int indent)
{
    const int width = 100;
    const char *p = text;
    int first = 1;
    while (*p) {
        size_t word = strcspn(p, " ");
        if (!first && column + 1 + (int)word > width) {
            fprintf(f, "\n%*s", indent, "");
            column = indent;
        } else if (!first) {
            fputc(' ', f);
            column++;
        }
        first = 0;
        fwrite(p, 1, word, f);
        column += (int)word;
        p += word;
        while (*p == ' ')
            p++;
    }
    fputc('\n', f);
}

void option_print_help(FILE *f)
{
    preset_words(1); /* their warnings, if any, before the options */
    preset_words(0);
    fputs("\n"
          "Renders the sky seen from one place as an equirectangular OpenEXR map (Blender's\n"
          "Environment Texture layout: north at u = 0.25, east at the centre, zenith at the top), or\n"
          "through a fisheye or pinhole camera, and a JSON sidecar with the sun's direction and light.\n"
          "Values are CIE-weighted radiance in linear Rec.709 or the --colorspace chosen (Y x 683 =\n"
          "cd/m^2), or spectral radiance with --wavelength.  Ranges are inclusive unless written (a, b].\n",
          f);
    const char *group = NULL;
    for (int i = 0; i < option_count; i++) {
        const option_spec *o = &option_specs[i];
        if (group != o->group) {
            group = o->group;
            fprintf(f, "\n%s:\n", group);
        }
        char head[64], text[1200];
        int n = snprintf(head, sizeof head, "  %s%s--%s%s%s", o->short_flag ? "-" : "",
                         o->short_flag ? (char[]){o->short_flag, ',', ' ', '\0'} : "", o->flag,
                         o->metavar ? " " : "", o->metavar ? o->metavar : "");
        /* the help from column 25, or after one space when the flag is longer */
        fprintf(f, "%s%*s", head, n < 25 ? 25 - n : 1, "");
        describe(o, 1, text, sizeof text);
        print_wrapped(f, text, n < 25 ? 25 : n + 1, 25);
    }
    fputs("\nExit status: 0 done, 1 runtime failure, 2 bad usage or input, 128+N stopped by signal N\n"
          "(130 for Ctrl-C).  An interrupted or failed run leaves no partial file and never replaces\n"
          "an existing one.\n",
          f);
}

/* ---- options --json ---------------------------------------------------------------------------- */

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *c = (const unsigned char *)s; *c; c++) {
        if (*c == '"' || *c == '\\')
            fprintf(f, "\\%c", *c);
        else if (*c < 0x20)
            fprintf(f, "\\u%04x", *c);
        else
            fputc(*c, f);
    }
    fputc('"', f);
}

static const char *kind_name(option_kind k)
{
    static const char *const names[] = {"number", "whole", "whole", "choice", "text",
                                        "switch", "date",  "time",  "utc_offset", "ratio"};
    return names[k];
}

/* The key a sky preset gives this option under, or NULL. */
static const char *preset_key(const option_spec *o, char *buf, size_t size)
{
    snprintf(buf, size, "%s", o->flag);
    for (char *c = buf; *c; c++)
        if (*c == '-')
            *c = '_';
    for (const char *const *k = fm_sky_preset_keys(); *k; k++)
        if (strcmp(*k, buf) == 0)
            return buf;
    return NULL;
}

/* The words as a JSON array ("none" and the biomes for --biome). */
static void json_words(FILE *f, const option_spec *o)
{
    char words[800];
    format_words(o, words, sizeof words);
    fputc('[', f);
    for (char *w = strtok(words, " |"); w; w = strtok(NULL, " |")) {
        if (w != words)
            fputs(", ", f);
        json_string(f, w);
    }
    fputc(']', f);
}

/* The default value itself: a number inside the range, a word, a string, false; null when the
 * default is "not given" (a sentinel) or comes from elsewhere (the date, the biome). */
static void json_default(FILE *f, const option_spec *o)
{
    static options defaults;
    options_set_defaults(&defaults);
    const char *at = (const char *)&defaults + o->offset;
    const fm_param_range *r = option_range(o);
    double v = 0.0;
    int i = 0;
    const char *s = NULL;
    switch (o->kind) {
    case OPTION_NUMBER:
    case OPTION_RATIO:
        memcpy(&v, at, sizeof v);
        break;
    case OPTION_WHOLE:
        memcpy(&i, at, sizeof i);
        v = i;
        break;
    case OPTION_SEED: {
        uint64_t u;
        memcpy(&u, at, sizeof u);
        v = (double)u;
        break;
    }
    case OPTION_CHOICE:
        memcpy(&i, at, sizeof i);
        for (const option_word *w = o->words; w->word; w++)
            if (w->value == i)
                s = w->word;
        break;
    case OPTION_TEXT:
        if (o->offset && !(o->flags & NOT_PARSED))
            memcpy(&s, at, sizeof s);
        break;
    case OPTION_SWITCH:
        fputs("false", f);
        return;
    default:
        fputs("null", f);
        return;
    }
    if (o->kind == OPTION_CHOICE || o->kind == OPTION_TEXT) {
        if (s)
            json_string(f, s);
        else
            fputs("null", f);
    } else if (o->kind == OPTION_RATIO || (r && (r->min_open ? v > r->min : v >= r->min) && v <= r->max)) {
        fprintf(f, "%.17g", v);
    } else {
        fputs("null", f);
    }
}

static void json_option(FILE *f, const option_spec *o)
{
    char key[48], text[1200];
    const fm_param_range *r = option_range(o);
    fprintf(f, "    {\"flag\": ");
    json_string(f, (snprintf(text, sizeof text, "--%s", o->flag), text));
    if (o->short_flag)
        fprintf(f, ", \"short\": \"-%c\"", o->short_flag);
    fprintf(f, ", \"kind\": \"%s\"", kind_name(o->kind));
    if (o->metavar) {
        fputs(", \"metavar\": ", f);
        json_string(f, o->metavar);
    }
    fputs(", \"preset_key\": ", f);
    if (preset_key(o, key, sizeof key))
        json_string(f, key);
    else
        fputs("null", f);
    if (o->field) {
        fputs(", \"field\": ", f);
        json_string(f, o->field);
    }
    if (r && o->kind != OPTION_OFFSET) {
        fprintf(f, ", \"min\": %.17g, \"max\": %.17g, \"min_open\": %s, \"unit\": ", r->min, r->max,
                r->min_open ? "true" : "false");
        json_string(f, r->unit);
    }
    if (o->words || (o->flags & (BIOME_WORDS | CLOUD_WORDS))) {
        fputs(", \"choices\": ", f);
        json_words(f, o);
    }
    fputs(", \"default\": ", f);
    json_default(f, o);
    format_default(o, text, sizeof text);
    if (text[0]) {
        fputs(", \"default_text\": ", f);
        json_string(f, text);
    }
    const char *needs = o->flags & NEEDS_FISHEYE   ? "--camera fisheye"
                        : o->flags & NEEDS_PINHOLE ? "--camera pinhole"
                        : o->flags & NEEDS_TIME    ? "--time or --time-start"
                                                   : NULL;
    if (needs)
        fprintf(f, ", \"needs\": \"%s\"", needs);
    if (o->flags & NEEDS_BUILTIN)
        fputs(", \"not_with\": \"--atmosphere\"", f);
    fputs(", \"group\": ", f);
    json_string(f, o->group);
    describe(o, 0, text, sizeof text);
    fputs(", \"help\": ", f);
    json_string(f, text);
    fputc('}', f);
}

void option_print_json(FILE *f)
{
    preset_words(1); /* their warnings, if any, before the JSON */
    preset_words(0);
    fprintf(f, "{\n  \"version\": \"%s\",\n  \"options\": [\n", FIRMAMENT_VERSION);
    for (int i = 0; i < option_count; i++) {
        json_option(f, &option_specs[i]);
        fputs(i + 1 < option_count ? ",\n" : "\n", f);
    }
    fputs("  ]\n}\n", f);
}

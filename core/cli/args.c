#include "args.h"
#include "numbers.h"
#include "option_table.h"
#include "time_args.h"
#include "usage.h"

#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FM_MAX_FRAMES 10000

void options_set_defaults(options *opt)
{
    static char cache_dir[4096]; /* the same for every render of the process */
    memset(opt, 0, sizeof *opt);
    opt->sky = fm_sky_params_default();
    if (cache_dir[0] || fm_default_cache_dir(cache_dir, sizeof cache_dir) == 0)
        opt->sky.cache_dir = cache_dir;
    opt->render = fm_render_params_default();
    opt->output = "sky.exr";
    opt->colorspace = "Linear Rec.709";
    opt->compression = FM_EXR_PIZ; /* lossless, and the smallest and fastest of the lossless on skies */
    opt->progress = PROGRESS_AUTO;
    opt->format = FORMAT_FROM_NAME;
}

const char *options_flag_for(const char *field)
{
    static char flag[64];
    const option_spec *o = option_for_field(field);
    if (!o)
        return NULL;
    snprintf(flag, sizeof flag, "--%s", o->flag);
    return flag;
}

void options_print_usage(void)
{
    command_print_help(stdout, command_find("render", NULL));
}

/* getopt's long options, from the table: the row's index + 256 as the value. */
static const struct option *long_options(void)
{
    static struct option list[128];
    if (list[0].name)
        return list;
    int n = 0;
    for (int i = 0; i < option_count && n + 1 < (int)(sizeof list / sizeof list[0]); i++) {
        const option_spec *o = &option_specs[i];
        if (strcmp(o->flag, "preset") == 0) /* expanded before (preset_args.c) */
            continue;
        list[n++] = (struct option){o->flag, o->metavar ? required_argument : no_argument, NULL, 256 + i};
    }
    return list;
}

/* ---- the sun from the date and time: --time, --utc-offset, refraction, time series ---------- */

typedef struct time_options {
    int time, start, end, step;                          /* given */
    const option_spec *solar_only;                       /* a refraction / Delta T option given */
    int sun_elevation, sun_azimuth, longitude; /* given, for the overrides and checks */
} time_options;

static int finish_time_options(options *opt, const time_options *t, int have_latitude, char *msg, size_t msg_size)
{
    const char *first = t->time ? "--time" : (t->start ? "--time-start" : (t->end ? "--time-end" : "--step"));
    if (!(t->time || t->start || t->end || t->step)) {
        if (t->solar_only) {
            snprintf(msg, msg_size, "--%s: applies only with --time or --time-start", t->solar_only->flag);
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


/* What the loop collects for the checks between options. */
typedef struct given_options {
    char given[128];                 /* by row */
    const option_spec *builtin_only; /* the last option about the built-in atmosphere */
    const option_spec *camera_only;  /* the last option of one camera only */
    const option_spec *solar_only;   /* the last input of the solar position */
} given_options;

static int was_given(const given_options *g, const char *flag)
{
    return g->given[option_find(flag) - option_specs];
}

static void *value_at(options *opt, const option_spec *o)
{
    return (char *)opt + o->offset;
}

static int set_number(const option_spec *o, const char *arg, options *opt, char *msg, size_t msg_size)
{
    double d;
    if (!parse_decimal(arg, &d)) {
        snprintf(msg, msg_size, "--%s: '%s' is not a number", o->flag, arg);
        return 0;
    }
    const fm_param_range *r = option_range(o);
    if (!((r->min_open ? d > r->min : d >= r->min) && d <= r->max)) {
        char range[64];
        option_format_range(r, range, sizeof range);
        snprintf(msg, msg_size, "--%s: %g is outside %s", o->flag, d, range);
        return 0;
    }
    memcpy(value_at(opt, o), &d, sizeof d);
    return 1;
}

static int set_whole(const option_spec *o, const char *arg, options *opt, char *msg, size_t msg_size)
{
    const fm_param_range *r = option_range(o);
    char range[64];
    option_format_range(r, range, sizeof range);
    long long n;
    if (!parse_whole(arg, o->kind == OPTION_SEED ? 0 : -INT_MAX, o->kind == OPTION_SEED ? (long long)r->max : INT_MAX,
                     &n)) {
        snprintf(msg, msg_size, "--%s: '%s' is not a whole number in %s", o->flag, arg, range);
        return 0;
    }
    if (n < r->min || n > r->max) {
        snprintf(msg, msg_size, "--%s: %lld is outside %s", o->flag, n, range);
        return 0;
    }
    if (o->kind == OPTION_SEED) {
        uint64_t u = (uint64_t)n;
        memcpy(value_at(opt, o), &u, sizeof u);
    } else {
        int v = (int)n;
        memcpy(value_at(opt, o), &v, sizeof v);
    }
    return 1;
}

static int set_choice(const option_spec *o, const char *arg, options *opt, char *msg, size_t msg_size)
{
    for (const option_word *w = o->words; w->word; w++)
        if (strcmp(arg, w->word) == 0) {
            memcpy(value_at(opt, o), &w->value, sizeof w->value);
            return 1;
        }
    int used = snprintf(msg, msg_size, "--%s: '%s' is not one of ", o->flag, arg);
    for (const option_word *w = o->words; w->word && used > 0 && (size_t)used < msg_size; w++)
        used += snprintf(msg + used, msg_size - (size_t)used, "%s%s", w == o->words ? "" : ", ", w->word);
    return 0;
}

/* Reads arg into the option's place; returns 0 with one line in msg when it is not a valid value. */
static int set_value(const option_spec *o, const char *arg, options *opt, char *msg, size_t msg_size)
{
    char flag[48];
    snprintf(flag, sizeof flag, "--%s", o->flag);
    switch (o->kind) {
    case OPTION_NUMBER:
        return set_number(o, arg, opt, msg, msg_size);
    case OPTION_WHOLE:
    case OPTION_SEED:
        return set_whole(o, arg, opt, msg, msg_size);
    case OPTION_CHOICE:
        return set_choice(o, arg, opt, msg, msg_size);
    case OPTION_TEXT:
        memcpy(value_at(opt, o), &arg, sizeof arg);
        return 1;
    case OPTION_SWITCH:
        memcpy(value_at(opt, o), &o->set_to, sizeof o->set_to);
        return 1;
    case OPTION_DATE:
        return parse_date_arg(flag, arg, &opt->sky.year, &opt->sky.month, &opt->sky.day, msg, msg_size);
    case OPTION_TIME:
        return parse_time_arg(flag, arg, strcmp(o->flag, "time-end") == 0 ? &opt->time_end_s : &opt->time_start_s,
                              msg, msg_size);
    case OPTION_OFFSET:
        return parse_utc_offset_arg(flag, arg, value_at(opt, o), msg, msg_size);
    case OPTION_RATIO:
        if (!parse_aspect(arg, value_at(opt, o))) {
            snprintf(msg, msg_size, "%s: '%s' is not a ratio W:H or a positive number", flag, arg);
            return 0;
        }
        return 1;
    }
    return 0;
}

/* getopt's report of an unknown option, a missing value or a value given to a switch. */
static void getopt_error(int c, char **argv, char *msg, size_t msg_size)
{
    if (c == ':')
        snprintf(msg, msg_size, "%s needs a value", argv[optind - 1]);
    else if (optopt >= 256 && strchr(argv[optind - 1], '='))
        snprintf(msg, msg_size, "%.*s takes no value", (int)strcspn(argv[optind - 1], "="), argv[optind - 1]);
    else if (optopt && optopt < 256)
        snprintf(msg, msg_size, "unknown option '-%c' (firmament --help lists the options)", optopt);
    else
        snprintf(msg, msg_size, "unknown option '%s' (firmament --help lists the options)", argv[optind - 1]);
}

/* Reads every option; returns PARSE_RUN when all were read, else PARSE_ERROR / PARSE_EXIT_OK. */
static parse_result read_options(int argc, char **argv, options *opt, given_options *g, char *msg, size_t msg_size)
{
    const struct option *list = long_options();
    int c, index = -1;
    while ((c = getopt_long(argc, argv, ":o:h", list, &index)) != -1) {
        const char *arg = optarg;
        const option_spec *o = NULL;
        if (c >= 256)
            o = &option_specs[c - 256];
        else
            for (int i = 0; i < option_count && c != ':' && c != '?'; i++)
                if (option_specs[i].short_flag == c)
                    o = &option_specs[i];
        if (!o) {
            getopt_error(c, argv, msg, msg_size);
            return PARSE_ERROR;
        }
        if (index >= 0 && abbreviated(argv, o->flag, arg)) {
            snprintf(msg, msg_size, "unknown option '%s' (options are given in full: --%s?)", option_token(argv, arg),
                     o->flag);
            return PARSE_ERROR;
        }
        index = -1;
        if (strcmp(o->flag, "help") == 0) {
            options_print_usage();
            return PARSE_EXIT_OK;
        }
        if ((o->flags & FILE_ARG) && arg[0] == '-' && arg[1] == '-') {
            /* `-o --width 64`: the path was left out and the next option taken for it */
            const char *tok = option_token(argv, arg);
            snprintf(msg, msg_size, "%s%s: '%s' looks like an option, not a file (a file of that name: ./%s)",
                     tok[1] == '-' ? "--" : "-", tok[1] == '-' ? o->flag : "o", arg, arg);
            return PARSE_ERROR;
        }
        if (!set_value(o, arg, opt, msg, msg_size))
            return PARSE_ERROR;
        g->given[o - option_specs] = 1;
        if (o->flags & NEEDS_BUILTIN)
            g->builtin_only = o;
        if (o->flags & (NEEDS_FISHEYE | NEEDS_PINHOLE))
            g->camera_only = o;
        if (o->flags & NEEDS_TIME)
            g->solar_only = o;
    }
    if (optind < argc) {
        snprintf(msg, msg_size, "unexpected argument '%s' (options start with --)", argv[optind]);
        return PARSE_ERROR;
    }
    return PARSE_RUN;
}

/* The checks between options (each value alone was checked as it was read). */
static int check_together(options *opt, const given_options *g, char *msg, size_t msg_size)
{
    int have_latitude = was_given(g, "latitude");
    const char *builtin_only = g->builtin_only ? g->builtin_only->flag : NULL;
    if ((have_latitude || was_given(g, "longitude")) && opt->sky.year == 0) {
        /* the place chooses the sun (with --time) and the ozone (with --date); alone it does nothing */
        snprintf(msg, msg_size, "--%s: applies only with --date (the ozone climatology) or --time (the sun)",
                 have_latitude ? "latitude" : "longitude");
        return 0;
    }
    if (opt->format == FORMAT_FROM_NAME) {
        const char *dot = strrchr(opt->output, '.');
        int hdr = dot && strlen(dot) == 4;
        for (int i = 0; hdr && i < 4; i++)
            hdr = dot[i] == ".hdr"[i] || dot[i] == ".HDR"[i];
        opt->format = hdr ? FORMAT_HDR : FORMAT_EXR;
    }
    if (opt->format == FORMAT_HDR && (opt->half || was_given(g, "compression"))) {
        snprintf(msg, msg_size, "%s: applies to EXR output, not to a Radiance picture (--format hdr or a .hdr name)",
                 opt->half ? "--half" : "--compression");
        return 0;
    }
    if (opt->render.reference_samples > 0 && opt->render.quality != FM_QUALITY_REFERENCE) {
        snprintf(msg, msg_size, "--samples: applies only with --quality reference");
        return 0;
    }
    if (opt->sky.atmosphere_file && !builtin_only && opt->sky.year != 0 && opt->sky.hour == FM_NO_TIME)
        builtin_only = "date"; /* without a time, the date is for the ozone climatology only */
    fm_camera_type needed = g->camera_only && (g->camera_only->flags & NEEDS_FISHEYE) ? FM_CAMERA_FISHEYE
                                                                                        : FM_CAMERA_PINHOLE;
    if (g->camera_only && opt->render.camera.type != needed) {
        snprintf(msg, msg_size, "--%s: applies only to --camera %s", g->camera_only->flag,
                 needed == FM_CAMERA_FISHEYE ? "fisheye" : "pinhole");
        return 0;
    }
    if (opt->sky.atmosphere_file && builtin_only) {
        snprintf(msg, msg_size, "--%s: does not apply with --atmosphere (the file defines every constituent)",
                 builtin_only);
        return 0;
    }
    if (opt->sky.year != 0 && !was_given(g, "ozone-du") && !opt->sky.atmosphere_file) {
        /* a date and a place choose the ozone column, unless --ozone-du says otherwise */
        if (!have_latitude) {
            snprintf(msg, msg_size, "--date: the ozone climatology also needs --latitude (or give --ozone-du)");
            return 0;
        }
        opt->sky.ozone_column_du = FM_OZONE_FROM_CLIMATOLOGY;
    }
    if (opt->preview && opt->sky.wavelength_nm > 0.0) {
        snprintf(msg, msg_size, "--preview: needs a colour render (not --wavelength)");
        return 0;
    }
    if (opt->spectral && (opt->sky.wavelength_nm > 0.0 || opt->frames > 0)) {
        snprintf(msg, msg_size, "--spectral: needs a single colour render (not --wavelength nor a time series)");
        return 0;
    }
    if (opt->sun_disk_map && (!opt->render.sun_disk || opt->frames > 0 || opt->spectral ||
                              opt->sky.wavelength_nm > 0.0 || opt->render.camera.type != FM_CAMERA_EQUIRECT)) {
        snprintf(msg, msg_size, "--sun-disk-map: needs a single colour equirect render with the disk (not "
                                "--no-sun-disk, a time series, --spectral or --wavelength)");
        return 0;
    }
    if (opt->have_exposure && !opt->preview) {
        snprintf(msg, msg_size, "--exposure: applies to --preview only");
        return 0;
    }
    return 1;
}

parse_result options_parse(int argc, char **argv, options *opt, char *msg, size_t msg_size)
{
    options_set_defaults(opt);
    opterr = 0; /* we print our own, one-line messages */
    optind = 1;
    given_options g = {0};
    parse_result r = read_options(argc, argv, opt, &g, msg, msg_size);
    if (r != PARSE_RUN)
        return r;
    opt->render.spectral = opt->spectral != NULL;
    opt->sky.threads = opt->render.threads;
    opt->have_exposure = was_given(&g, "exposure");
    time_options times = {.time = was_given(&g, "time"),
                          .start = was_given(&g, "time-start"),
                          .end = was_given(&g, "time-end"),
                          .step = was_given(&g, "step"),
                          .solar_only = g.solar_only,
                          .sun_elevation = was_given(&g, "sun-elevation"),
                          .sun_azimuth = was_given(&g, "sun-azimuth"),
                          .longitude = was_given(&g, "longitude")};
    if (!finish_time_options(opt, &times, was_given(&g, "latitude"), msg, msg_size) ||
        !check_together(opt, &g, msg, msg_size))
        return PARSE_ERROR;
    return PARSE_RUN;
}

#include "batch_plan.h"
#include "batch_epw.h"
#include "batch_job.h"
#include "numbers.h"
#include "report.h"
#include "time_args.h"
#include "usage.h"

#include "base/date.h"
#include "base/platform.h"
#include "base/sealed_file.h"
#include "firmament/firmament.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { EXIT_RUNTIME = 1, EXIT_USAGE = 2, MOST = 64 };


typedef struct place {
    char name[64];
    double latitude_deg, longitude_deg;
    int utc_offset_min;
} place;

/* One sky to render for each preset: a place, a date and a time, and from a weather file its
 * aerosol, albedo and cloud cover (NULL: none). */
typedef struct moment {
    int place; /* index into places, -1 for the preset's own */
    int year, month, day; /* 0: the preset's date */
    int seconds;          /* of the day; -1: the preset's time */
    const epw_hour *weather;
} moment;

typedef struct plan_args {
    const char *manifest, *out_dir, *epw;
    const char *presets[MOST];
    int n_presets;
    place places[MOST];
    int n_places;
    int y0, m0, d0, y1, m1, d1; /* date range, y0 = 0: none */
    int times[1440];
    int n_times;
    int t_start, t_end, have_start, have_end;
    double step_min, sun_above_deg;
    int have_sun_above;
    const char *sets[MOST];
    int n_sets;
    long long seed;
} plan_args;

/* One line "batch plan: ..." on stderr; returns 0 (parse failed). */
static int fail(const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    report_error("batch plan: %s", line);
    return 0;
}

static int parse_place(const char *v, place *p)
{
    char name[64], lat[64], lon[64], utc[64];
    char msg[256];
    if (sscanf(v, "%63[^,],%63[^,],%63[^,],%63s", name, lat, lon, utc) != 4 ||
        !parse_decimal(lat, &p->latitude_deg) || fabs(p->latitude_deg) > 90.0 || !parse_decimal(lon, &p->longitude_deg) ||
        fabs(p->longitude_deg) > 180.0 || strspn(name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-") != strlen(name))
        return fail("--place: '%s' is not NAME,LAT,LON,UTC_OFFSET (e.g. paris,48.857,2.352,+01:00; a name of "
                    "letters, digits and '-')", v);
    if (!parse_utc_offset_arg("--place", utc, &p->utc_offset_min, msg, sizeof msg))
        return fail("%s", msg);
    snprintf(p->name, sizeof p->name, "%s", name);
    return 1;
}

static int parse_times(const char *v, plan_args *a)
{
    char buf[64], msg[256];
    for (const char *s = v; *s;) {
        size_t n = strcspn(s, ",");
        snprintf(buf, sizeof buf, "%.*s", (int)(n < 63 ? n : 63), s);
        if (a->n_times == (int)(sizeof a->times / sizeof a->times[0]))
            return fail("--times: more than 1440 times");
        if (!parse_time_arg("--times", buf, &a->times[a->n_times++], msg, sizeof msg))
            return fail("%s", msg);
        s += n + (s[n] == ',');
    }
    return 1;
}

static int parse_plan_args(int argc, char **argv, plan_args *a)
{
    memset(a, 0, sizeof *a);
    a->out_dir = "maps";
    char msg[256];
    for (int i = 1; i < argc; i++) {
        const char *f = argv[i];
        int takes = strcmp(f, "-o") == 0 || (f[0] == '-' && f[1] == '-');
        if (!takes || (i + 1 >= argc)) {
            if (takes)
                return fail("%s needs a value", f);
            return fail("unexpected '%s' (%s)", f, command_usage_line("batch plan"));
        }
        const char *v = argv[++i];
        double x;
        long long w;
        if (!strcmp(f, "-o"))
            a->manifest = v;
        else if (!strcmp(f, "--out-dir"))
            a->out_dir = v;
        else if (!strcmp(f, "--epw"))
            a->epw = v;
        else if (!strcmp(f, "--preset") && a->n_presets < MOST)
            a->presets[a->n_presets++] = v;
        else if (!strcmp(f, "--set") && a->n_sets < MOST) {
            if (!strchr(v, '=') || v[0] == '=')
                return fail("--set: '%s' is not KEY=VALUE (a preset's key, e.g. width=1024)", v);
            a->sets[a->n_sets++] = v;
        } else if (!strcmp(f, "--place") && a->n_places < MOST) {
            if (!parse_place(v, &a->places[a->n_places++]))
                return 0;
        } else if (!strcmp(f, "--date") || !strcmp(f, "--date-start")) {
            if (!parse_date_arg(f, v, &a->y0, &a->m0, &a->d0, msg, sizeof msg) || !date_is_valid(a->y0, a->m0, a->d0))
                return fail("%s: '%s' is not a date YYYY-MM-DD in 1900-2100", f, v);
            if (!strcmp(f, "--date"))
                a->y1 = a->y0, a->m1 = a->m0, a->d1 = a->d0;
        } else if (!strcmp(f, "--date-end")) {
            if (!parse_date_arg(f, v, &a->y1, &a->m1, &a->d1, msg, sizeof msg) || !date_is_valid(a->y1, a->m1, a->d1))
                return fail("%s: '%s' is not a date YYYY-MM-DD in 1900-2100", f, v);
        } else if (!strcmp(f, "--times")) {
            if (!parse_times(v, a))
                return 0;
        } else if (!strcmp(f, "--time-start") || !strcmp(f, "--time-end")) {
            int *t = f[7] == 's' ? &a->t_start : &a->t_end;
            if (!parse_time_arg(f, v, t, msg, sizeof msg))
                return fail("%s", msg);
            *(f[7] == 's' ? &a->have_start : &a->have_end) = 1;
        } else if (!strcmp(f, "--step")) {
            if (!parse_decimal(v, &a->step_min) || !(a->step_min >= 1.0 && a->step_min <= 1440.0))
                return fail("--step: '%s' is not a number of minutes in [1, 1440]", v);
        } else if (!strcmp(f, "--sun-above")) {
            if (!parse_decimal(v, &x) || fabs(x) > 90.0)
                return fail("--sun-above: '%s' is not an elevation in [-90, 90] degrees", v);
            a->sun_above_deg = x;
            a->have_sun_above = 1;
        } else if (!strcmp(f, "--seed")) {
            if (!parse_whole(v, 0, 1LL << 52, &w))
                return fail("--seed: '%s' is not a whole number in [0, 2^52]", v);
            a->seed = w;
        } else {
            return fail("unknown option '%s' (%s)", f, command_usage_line("batch plan"));
        }
    }
    if (!a->manifest)
        return fail("%s", command_usage_line("batch plan"));
    if ((a->have_start || a->have_end || a->step_min > 0.0) && !(a->have_start && a->have_end && a->step_min > 0.0))
        return fail("--time-start, --time-end and --step go together");
    if (a->have_start && a->n_times)
        return fail("--times or --time-start, not both");
    for (int t = a->t_start; a->have_start && t <= a->t_end; t = a->t_start + (int)lround(++a->n_times * a->step_min * 60.0))
        if (a->n_times == (int)(sizeof a->times / sizeof a->times[0]))
            return fail("--time-start ... --step: more than 1440 times");
        else
            a->times[a->n_times] = t;
    if (a->y0 && !a->y1)
        return fail("--date-start needs --date-end");
    if (a->y1 && !a->y0)
        return fail("--date-end needs --date-start");
    if (a->epw && (a->n_places || a->y0 || a->n_times))
        return fail("--epw gives the place, dates and times: not with --place, --date or --times");
    if (a->have_sun_above && !a->epw && !(a->n_places && a->y0 && a->n_times))
        return fail("--sun-above needs --place, a date and times (or --epw)");
    return 1;
}

/* ---- the moments ----------------------------------------------------------------------------- */

static int sun_elevation(const place *p, int y, int mo, int d, int seconds, double elevation_m, double *out)
{
    fm_solar_params sp = fm_solar_params_default();
    sp.year = y, sp.month = mo, sp.day = d;
    sp.hour = seconds / 3600, sp.minute = seconds / 60 % 60, sp.second = seconds % 60;
    sp.utc_offset_min = p->utc_offset_min;
    sp.latitude_deg = p->latitude_deg;
    sp.longitude_deg = p->longitude_deg;
    sp.elevation_m = elevation_m;
    fm_solar_position pos;
    fm_error err = {0};
    if (fm_solar_position_compute(&sp, &pos, &err))
        return 0;
    *out = pos.elevation_deg;
    return 1;
}

static void next_day(int *y, int *m, int *d)
{
    if (++*d > date_days_in_month(*y, *m)) {
        *d = 1;
        if (++*m > 12)
            *m = 1, ++*y;
    }
}

static int add_moment(moment **list, int *n, moment mo)
{
    if (*n % 1024 == 0) {
        moment *bigger = realloc(*list, (size_t)(*n + 1024) * sizeof *bigger);
        if (!bigger)
            return 0;
        *list = bigger;
    }
    (*list)[(*n)++] = mo;
    return 1;
}

/* places x dates x times, those with the sun above the limit */
static int grid_moments(const plan_args *a, moment **list, int *n)
{
    int n_places = a->n_places ? a->n_places : 1;
    for (int p = 0; p < n_places; p++) {
        int y = a->y0, m = a->m0, d = a->d0;
        for (int day = 0; day < 200000; day++) {
            for (int t = 0; t < (a->n_times ? a->n_times : 1); t++) {
                moment mo = {a->n_places ? p : -1, y, m, d, a->n_times ? a->times[t] : -1, NULL};
                double el;
                if (a->have_sun_above && sun_elevation(&a->places[p], y, m, d, mo.seconds, 0.0, &el) &&
                    el <= a->sun_above_deg)
                    continue;
                if (!add_moment(list, n, mo))
                    return 0;
            }
            if (!a->y0 || (y == a->y1 && m == a->m1 && d == a->d1) || y > a->y1)
                break;
            next_day(&y, &m, &d);
        }
    }
    return 1;
}

static int epw_moments(const plan_args *a, const epw_file *e, place *p, moment **list, int *n)
{
    snprintf(p->name, sizeof p->name, "%s", e->city);
    p->latitude_deg = e->latitude_deg;
    p->longitude_deg = e->longitude_deg;
    p->utc_offset_min = e->utc_offset_min;
    for (int i = 0; i < e->count; i++) {
        const epw_hour *h = &e->hours[i];
        double el;
        if (!sun_elevation(p, h->year, h->month, h->day, h->minute_of_day * 60, e->elevation_m, &el))
            continue;
        if (el <= (a->have_sun_above ? a->sun_above_deg : 0.0))
            continue;
        if (!add_moment(list, n, (moment){0, h->year, h->month, h->day, h->minute_of_day * 60, h}))
            return 0;
    }
    return 1;
}

/* ---- the jobs ---------------------------------------------------------------------------------- */

static void set_item(cJSON *job, const char *key, cJSON *item)
{
    if (cJSON_GetObjectItemCaseSensitive(job, key))
        cJSON_ReplaceItemInObjectCaseSensitive(job, key, item);
    else
        cJSON_AddItemToObject(job, key, item);
}

/* --set KEY=VALUE: a number where it reads as one, true/false, else text */
static void apply_set(cJSON *job, const char *set)
{
    char key[64];
    size_t n = strcspn(set, "=");
    snprintf(key, sizeof key, "%.*s", (int)(n < 63 ? n : 63), set);
    const char *v = set + n + 1;
    double x;
    if (parse_decimal(v, &x))
        set_item(job, key, cJSON_CreateNumber(x));
    else if (!strcmp(v, "true") || !strcmp(v, "false"))
        set_item(job, key, cJSON_CreateBool(v[0] == 't'));
    else
        set_item(job, key, cJSON_CreateString(v));
}

static cJSON *make_job(const plan_args *a, const char *preset, const place *pl, const moment *mo, long long seed,
                       const char *stem)
{
    cJSON *job = cJSON_CreateObject();
    if (preset)
        cJSON_AddStringToObject(job, "preset", preset);
    for (int i = 0; i < a->n_sets; i++)
        apply_set(job, a->sets[i]);
    char text[64];
    if (pl) {
        char utc[8];
        format_utc_offset(pl->utc_offset_min, utc, sizeof utc);
        set_item(job, "latitude", cJSON_CreateNumber(pl->latitude_deg));
        set_item(job, "longitude", cJSON_CreateNumber(pl->longitude_deg));
        set_item(job, "utc_offset", cJSON_CreateString(utc));
    }
    if (mo->year) {
        snprintf(text, sizeof text, "%04d-%02d-%02d", mo->year, mo->month, mo->day);
        set_item(job, "date", cJSON_CreateString(text));
    }
    if (mo->seconds >= 0) {
        format_time_of_day(mo->seconds, text, sizeof text);
        set_item(job, "time", cJSON_CreateString(text));
    }
    const epw_hour *w = mo->weather;
    if (w && w->aod550 >= 0.0)
        set_item(job, "aod550", cJSON_CreateNumber(w->aod550));
    if (w && w->albedo >= 0.0)
        set_item(job, "albedo", cJSON_CreateNumber(w->albedo));
    if (w && w->sky_cover_tenths >= 0)
        set_item(job, "sky_cover_tenths", cJSON_CreateNumber(w->sky_cover_tenths));
    set_item(job, "seed", cJSON_CreateNumber((double)seed));
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.exr", a->out_dir, stem);
    set_item(job, "output", cJSON_CreateString(path));
    snprintf(path, sizeof path, "%s/%s.json", a->out_dir, stem);
    set_item(job, "sidecar", cJSON_CreateString(path));
    return job;
}

/* "clear-noon_paris_20250621_1200": the preset's name (its file's, without .json), the place, the
 * date and time, each where the plan gives it */
static void job_stem(const char *preset, const place *pl, const moment *mo, char *out, size_t size)
{
    size_t n = 0;
    out[0] = '\0';
    if (preset) {
        const char *slash = platform_last_separator(preset);
        const char *base = slash ? slash + 1 : preset;
        size_t len = strlen(base);
        if (len > 5 && !strcmp(base + len - 5, ".json"))
            len -= 5;
        n += (size_t)snprintf(out + n, size - n, "%.*s", (int)len, base);
    }
    if (pl && n < size)
        n += (size_t)snprintf(out + n, size - n, "%s%s", n ? "_" : "", pl->name);
    if (mo->year && n < size)
        n += (size_t)snprintf(out + n, size - n, "%s%04d%02d%02d", n ? "_" : "", mo->year, mo->month, mo->day);
    if (mo->seconds >= 0 && n < size)
        n += (size_t)snprintf(out + n, size - n, "%s%02d%02d", n ? "_" : "", mo->seconds / 3600, mo->seconds / 60 % 60);
    if (!n)
        snprintf(out, size, "sky");
}

/* Why a folder could not be made (errno): EEXIST, a file where a folder of its path should be. */
static const char *folder_error(void)
{
    return errno == EEXIST ? "a file of that name is in its path" : strerror(errno);
}

static int write_manifest(const plan_args *a, const moment *moments, int n_moments, const place *places)
{
    int n_presets = a->n_presets ? a->n_presets : 1;
    size_t cap = 1 << 16, len = 0;
    char *text = malloc(cap);
    manifest m = {.dir = (char *)""};
    const char *slash = platform_last_separator(a->manifest);
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - a->manifest + 1) : 0, a->manifest);
    m.dir = dir;
    int code = 0;
    long long index = 0;
    for (int p = 0; p < n_presets && text && !code; p++)
        for (int i = 0; i < n_moments && !code; i++, index++) {
            const char *preset = a->n_presets ? a->presets[p] : NULL;
            const place *pl = moments[i].place >= 0 ? &places[moments[i].place] : NULL;
            char stem[512], msg[1024];
            job_stem(preset, pl, &moments[i], stem, sizeof stem);
            cJSON *job = make_job(a, preset, pl, &moments[i], a->seed + index, stem);
            char *line = job ? cJSON_PrintUnformatted(job) : NULL;
            if (!line) {
                report_error("out of memory");
                code = EXIT_RUNTIME;
            } else if (job_check(&m, job, msg, sizeof msg)) {
                report_error("batch plan: job %lld (%s): %s", index, stem, msg);
                code = EXIT_USAGE;
            } else {
                size_t n = strlen(line);
                while (text && len + n + 2 > cap) {
                    char *bigger = realloc(text, cap *= 2);
                    if (!bigger)
                        free(text);
                    text = bigger;
                }
                if (text) {
                    memcpy(text + len, line, n);
                    len += n;
                    text[len++] = '\n';
                }
            }
            free(line);
            cJSON_Delete(job);
        }
    if (!text && !code) {
        report_error("out of memory");
        code = EXIT_RUNTIME;
    }
    if (!code && index == 0) {
        report_error("batch plan: no jobs (the sun is never above %g degrees at those times)", a->sun_above_deg);
        code = EXIT_USAGE;
    }
    /* the manifest's folder and the maps' are made as `mkdir -p` would, once the jobs are good */
    char out_dir[4096];
    snprintf(out_dir, sizeof out_dir, "%s%s", a->out_dir[0] == '/' ? "" : dir, a->out_dir);
    size_t dir_len = strlen(dir) > 1 ? strlen(dir) - 1 : strlen(dir); /* without its last '/' */
    if (!code && dir[0] && sealed_file_make_dirs(dir) != 0) {
        report_error("batch plan: -o: cannot create the folder '%.*s': %s", (int)dir_len, dir, folder_error());
        code = EXIT_USAGE;
    }
    if (!code && sealed_file_make_dirs(out_dir) != 0) {
        report_error("batch plan: --out-dir: cannot create the folder '%s': %s", out_dir, folder_error());
        code = EXIT_USAGE;
    }
    if (!code && write_file_atomic(a->manifest, text, len) != 0) {
        report_error("batch plan: cannot write '%s': %s", a->manifest, strerror(errno));
        code = EXIT_USAGE;
    }
    if (!code)
        printf("wrote %s: %lld jobs, maps in %s\n", a->manifest, index, out_dir);
    free(text);
    return code;
}

int batch_plan(int argc, char **argv)
{
    plan_args *a = malloc(sizeof *a);
    if (!a) {
        report_error("out of memory");
        return EXIT_RUNTIME;
    }
    if (!parse_plan_args(argc, argv, a)) {
        free(a);
        return EXIT_USAGE;
    }
    moment *moments = NULL;
    int n = 0, ok = 1, code = 0;
    epw_file e = {0};
    place epw_place;
    if (a->epw) {
        char msg[1024];
        if (epw_read(a->epw, &e, msg, sizeof msg)) {
            report_error("%s", msg);
            code = EXIT_USAGE;
        } else {
            ok = epw_moments(a, &e, &epw_place, &moments, &n);
        }
    } else {
        ok = grid_moments(a, &moments, &n);
    }
    if (!code && !ok) {
        report_error("out of memory");
        code = EXIT_RUNTIME;
    }
    if (!code)
        code = write_manifest(a, moments, n, a->epw ? &epw_place : a->places);
    free(moments);
    epw_free(&e);
    free(a);
    return code;
}

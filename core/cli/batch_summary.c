#include "batch_summary.h"
#include "batch_job.h"
#include "report.h"
#include "usage.h"

#include "base/date.h"
#include "base/platform.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { EXIT_RUNTIME = 1, EXIT_USAGE = 2 };

/* The heat map: one cell per day of the year (columns) and hour of the day (rows, midnight at the
 * top), CELL_W x CELL_H pixels each. */
enum { DAYS = 366, HOURS = 24, CELL_W = 2, CELL_H = 8 };

typedef struct text_buf {
    char *s;
    size_t len, cap;
} text_buf;

static int append(text_buf *b, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
        va_end(ap);
        if (n < 0)
            return -1;
        if (b->s && b->len + (size_t)n < b->cap) {
            b->len += (size_t)n;
            return 0;
        }
        size_t cap = (b->cap ? 2 * b->cap : 1 << 16) + (size_t)n;
        char *bigger = realloc(b->s, cap);
        if (!bigger)
            return -1;
        b->s = bigger;
        b->cap = cap;
    }
}

static double number_at(const cJSON *root, const char *group, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(root, group), key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static cJSON *read_json(const char *path)
{
    FILE *f = path ? platform_fopen(path, "rb") : NULL;
    if (!f)
        return NULL;
    text_buf b = {0};
    char chunk[8192];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0)
        if (append(&b, "%.*s", (int)n, chunk))
            break;
    fclose(f);
    cJSON *root = b.s ? cJSON_Parse(b.s) : NULL;
    free(b.s);
    return root;
}

/* A colour for t in [0, 1]: dark blue through green to yellow (a viridis-like ramp, linear between
 * five stops); night and missing hours are black. */
static void ramp(double t, unsigned char *rgb)
{
    static const unsigned char stops[5][3] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double x = t * 4.0;
    int i = x >= 4.0 ? 3 : (int)x;
    double f = x - i;
    for (int c = 0; c < 3; c++)
        rgb[c] = (unsigned char)lround(stops[i][c] + f * (stops[i + 1][c] - stops[i][c]));
}

static void png_to_buffer(png_structp png, png_bytep data, png_size_t n)
{
    text_buf *b = png_get_io_ptr(png);
    if (b->len + n > b->cap) {
        size_t cap = 2 * (b->len + n);
        char *bigger = realloc(b->s, cap);
        if (!bigger)
            png_error(png, "out of memory");
        b->s = bigger;
        b->cap = cap;
    }
    memcpy(b->s + b->len, data, n);
    b->len += n;
}

/* The heat map as PNG bytes into out; lux[day][hour] < 0 is black. */
static int heat_map_png(const double (*lux)[HOURS], double max_lux, text_buf *out)
{
    const int w = DAYS * CELL_W, h = HOURS * CELL_H;
    unsigned char *pixels = calloc((size_t)w * h * 3, 1);
    png_structp png = pixels ? png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL) : NULL;
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        free(pixels);
        return -1;
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double v = lux[x / CELL_W][y / CELL_H];
            unsigned char *p = pixels + ((size_t)y * w + x) * 3;
            if (v >= 0.0 && max_lux > 0.0)
                ramp(v / max_lux, p);
        }
    png_set_write_fn(png, out, png_to_buffer, NULL);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_text text[1] = {{.compression = PNG_TEXT_COMPRESSION_NONE, .key = "Description"}};
    char desc[256];
    snprintf(desc, sizeof desc,
             "global horizontal illuminance: day of year 1-366 left to right, hour 0-23 top to bottom, "
             "colour 0 to %.0f lux (black: night or no map)", max_lux);
    text[0].text = desc;
    png_set_text(png, info, text, 1);
    png_write_info(png, info);
    for (int y = 0; y < h; y++)
        png_write_row(png, pixels + (size_t)y * w * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(pixels);
    return 0;
}


/* path with its extension replaced by ext (".csv"), into out */
static void with_extension(const char *path, const char *ext, char *out, size_t size)
{
    size_t n = strlen(path);
    const char *dot = strrchr(path, '.');
    const char *slash = platform_last_separator(path);
    if (dot && (!slash || dot > slash))
        n = (size_t)(dot - path);
    snprintf(out, size, "%.*s%s", (int)n, path, ext);
}

/* One CSV row for job i (its sidecar read if there; *found 1 when it was); the map's cell filled. */
static int summary_row(const manifest *m, int i, text_buf *csv, double (*lux)[HOURS], double *max_lux, int *found)
{
    const cJSON *job = m->jobs[i];
    char *sidecar_path = manifest_path(m, job, "sidecar");
    cJSON *side = read_json(sidecar_path);
    free(sidecar_path);
    *found = side != NULL;
    const cJSON *date = cJSON_GetObjectItemCaseSensitive(job, "date");
    const cJSON *time = cJSON_GetObjectItemCaseSensitive(job, "time");
    const cJSON *cover = cJSON_GetObjectItemCaseSensitive(job, "sky_cover_tenths");
    const cJSON *out = cJSON_GetObjectItemCaseSensitive(job, "output");
    const cJSON *p = cJSON_GetObjectItemCaseSensitive(side, "parameters");
    const cJSON *sdate = cJSON_GetObjectItemCaseSensitive(p, "date"), *stime = cJSON_GetObjectItemCaseSensitive(p, "time");
    const char *d = cJSON_IsString(sdate) ? sdate->valuestring : cJSON_IsString(date) ? date->valuestring : "";
    const char *t = cJSON_IsString(stime) ? stime->valuestring : cJSON_IsString(time) ? time->valuestring : "";
    double v[7] = {number_at(side, "sun", "elevation_deg"),
                   number_at(side, "sun", "azimuth_deg"),
                   number_at(side, "sun", "direct_normal_illuminance_lux"),
                   number_at(side, "sun", "direct_horizontal_illuminance_lux"),
                   number_at(side, "sky", "diffuse_horizontal_illuminance_lux"),
                   number_at(side, "sky", "global_horizontal_illuminance_lux"),
                   number_at(side, "atmosphere", "aerosol_optical_depth_550nm")};
    int tenths = cJSON_IsNumber(cover) ? cover->valueint : -1;
    const char *flag = !side ? "missing" : tenths >= 5 ? "cloudy" : "";
    int rc = append(csv, "%d,%s,%s,%s", i, d, t, cJSON_IsString(out) ? out->valuestring : "");
    for (int k = 0; k < 7 && !rc; k++)
        rc = isnan(v[k]) ? append(csv, ",") : append(csv, ",%.6g", v[k]);
    if (!rc)
        rc = tenths >= 0 ? append(csv, ",%d,%s\n", tenths, flag) : append(csv, ",,%s\n", flag);
    int y, mo, dd, hh;
    if (side && !isnan(v[5]) && sscanf(d, "%d-%d-%d", &y, &mo, &dd) == 3 && sscanf(t, "%d", &hh) == 1 &&
        date_day_of_year(y, mo, dd) > 0 && hh >= 0 && hh < HOURS) {
        lux[date_day_of_year(y, mo, dd) - 1][hh] = v[5];
        *max_lux = fmax(*max_lux, v[5]);
    }
    cJSON_Delete(side);
    return rc;
}

int batch_summary(int argc, char **argv)
{
    const char *path = NULL, *csv_path = NULL, *png_path = NULL;
    for (int i = 1; i < argc; i++) {
        if ((!strcmp(argv[i], "-o") || !strcmp(argv[i], "--png")) && i + 1 < argc) {
            *(argv[i][1] == 'o' ? &csv_path : &png_path) = argv[i + 1];
            i++;
        } else if (argv[i][0] == '-' || path) {
            report_error("batch summary: unexpected '%s' (%s)", argv[i], command_usage_line("batch summary"));
            return EXIT_USAGE;
        } else {
            path = argv[i];
        }
    }
    if (!path) {
        report_error("%s", command_usage_line("batch summary"));
        return EXIT_USAGE;
    }
    char csv_default[4096], png_default[4096];
    with_extension(path, ".csv", csv_default, sizeof csv_default);
    with_extension(path, ".png", png_default, sizeof png_default);
    csv_path = csv_path ? csv_path : csv_default;
    png_path = png_path ? png_path : png_default;
    manifest m;
    if (manifest_open(path, &m))
        return EXIT_USAGE;
    double(*lux)[HOURS] = malloc(sizeof(double[DAYS][HOURS]));
    text_buf csv = {0}, png = {0};
    double max_lux = 0.0;
    int rc = !lux || append(&csv, "index,date,time,output,sun_elevation_deg,sun_azimuth_deg,"
                                  "direct_normal_illuminance_lux,direct_horizontal_illuminance_lux,"
                                  "diffuse_horizontal_illuminance_lux,global_horizontal_illuminance_lux,"
                                  "aod550,sky_cover_tenths,flags\n");
    for (int d = 0; lux && d < DAYS; d++)
        for (int h = 0; h < HOURS; h++)
            lux[d][h] = -1.0;
    int done = 0;
    for (int i = 0; i < m.count && !rc; i++) {
        int found = 0;
        rc = summary_row(&m, i, &csv, lux, &max_lux, &found);
        done += found;
    }
    int code = 0;
    if (rc || heat_map_png((const double(*)[HOURS])lux, max_lux, &png)) {
        report_error("out of memory");
        code = EXIT_RUNTIME;
    } else if (write_file_atomic(csv_path, csv.s, csv.len)) {
        report_error("batch summary: cannot write '%s': %s", csv_path, strerror(errno));
        code = EXIT_USAGE;
    } else if (write_file_atomic(png_path, png.s, png.len)) {
        report_error("batch summary: cannot write '%s': %s", png_path, strerror(errno));
        code = EXIT_USAGE;
    } else {
        printf("wrote %s (%d jobs, %d with their sidecar) and %s (global horizontal illuminance, 0 to %.0f lux)\n",
               csv_path, m.count, done, png_path, max_lux);
    }
    free(csv.s);
    free(png.s);
    free(lux);
    manifest_free(&m);
    return code;
}

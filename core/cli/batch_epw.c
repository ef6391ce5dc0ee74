#include "batch_epw.h"

#include "numbers.h"

#include "base/date.h"
#include "base/platform.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The data fields read (1-based, as the EnergyPlus documentation numbers them). */
enum { F_YEAR = 1, F_MONTH, F_DAY, F_HOUR, F_MINUTE, F_TOTAL_SKY_COVER = 23, F_AOD = 30, F_ALBEDO = 33, N_FIELDS = 35 };

/* Broadband aerosol optical depth (the EPW's field, from TMY3's "AOD") to the optical depth at
 * 550 nm: the broadband value equals the spectral one near 700 nm (Molineaux, Ineichen & O'Neill,
 * Solar Energy 64 (1998) 21-28), carried to 550 nm with Angstrom exponent 1.3 (Angstrom 1929):
 * (700/550)^1.3 = 1.368. */
#define EPW_AOD_TO_550 1.368

static const char *field_name(int f)
{
    switch (f) {
    case F_YEAR: return "Year";
    case F_MONTH: return "Month";
    case F_DAY: return "Day";
    case F_HOUR: return "Hour";
    case F_MINUTE: return "Minute";
    case F_TOTAL_SKY_COVER: return "Total Sky Cover";
    case F_AOD: return "Aerosol Optical Depth";
    case F_ALBEDO: return "Albedo";
    default: return "";
    }
}

/* Splits line at commas into at most n fields (in place); returns the count. */
static int split(char *line, char **fields, int n)
{
    int k = 0;
    for (char *s = line; k < n;) {
        fields[k++] = s;
        char *comma = strchr(s, ',');
        if (!comma)
            break;
        *comma = '\0';
        s = comma + 1;
    }
    return k;
}

/* The missing-value codes of the format: 9, 99, 999, 9999, 99999 and 0.999 (an AOD). */
static int is_missing_code(double x)
{
    return x == 9 || x == 99 || x == 999 || x == 9999 || x == 99999 || x == 0.999;
}

typedef struct reader {
    const char *path;
    int line;
    char *msg;
    size_t msg_size;
} reader;

static int bad(reader *r, int field, const char *what, const char *value)
{
    snprintf(r->msg, r->msg_size, "%s: line %d, field %d%s%s%s: '%s' %s", r->path, r->line, field,
             field_name(field)[0] ? " (" : "", field_name(field), field_name(field)[0] ? ")" : "", value, what);
    return 2;
}

static int number(reader *r, char **fields, int f, double lo, double hi, double *out)
{
    char text[64];
    const char *v = fields[f - 1];
    if (v[0] == '.') { /* ".999", as the format writes the AOD's missing code */
        snprintf(text, sizeof text, "0%s", v);
        v = text;
    }
    if (!parse_decimal(v, out) || *out < lo || *out > hi)
        return bad(r, f, "is not a number in range", fields[f - 1]);
    return 0;
}

/* LOCATION,City,State,Country,Source,WMO,Latitude,Longitude,TimeZone,Elevation */
static int read_location(reader *r, char *line, epw_file *e)
{
    char *f[10];
    double lat, lon, tz, elev;
    if (split(line, f, 10) != 10 || strcmp(f[0], "LOCATION") != 0)
        return bad(r, 1, "is not a LOCATION line of 10 fields", f[0]);
    if (!parse_decimal(f[6], &lat) || fabs(lat) > 90.0)
        return bad(r, 7, "is not a latitude in [-90, 90]", f[6]);
    if (!parse_decimal(f[7], &lon) || fabs(lon) > 180.0)
        return bad(r, 8, "is not a longitude in [-180, 180]", f[7]);
    if (!parse_decimal(f[8], &tz) || tz < -12.0 || tz > 14.0)
        return bad(r, 9, "is not a time zone in hours [-12, 14]", f[8]);
    if (!parse_decimal(f[9], &elev) || elev < -1000.0 || elev > 9999.9)
        return bad(r, 10, "is not an elevation in metres [-1000, 9999.9]", f[9]);
    /* the city becomes part of file names: letters and digits kept, the rest '-' */
    size_t n = 0;
    for (const char *c = f[1]; *c && n + 1 < sizeof e->city; c++)
        e->city[n++] = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ? *c : '-';
    e->city[n] = '\0';
    if (!n)
        snprintf(e->city, sizeof e->city, "epw");
    e->latitude_deg = lat;
    e->longitude_deg = lon;
    e->utc_offset_min = (int)lround(tz * 60.0);
    e->elevation_m = elev;
    return 0;
}

static int read_hour(reader *r, char *line, epw_hour *h)
{
    char *f[N_FIELDS + 1];
    int n = split(line, f, N_FIELDS + 1);
    if (n < N_FIELDS) {
        snprintf(r->msg, r->msg_size, "%s: line %d: %d fields, an EPW data line has %d", r->path, r->line, n, N_FIELDS);
        return 2;
    }
    double y, mo, d, hr, x;
    if (number(r, f, F_YEAR, 1900, 2100, &y) || number(r, f, F_MONTH, 1, 12, &mo) || number(r, f, F_DAY, 1, 31, &d) ||
        number(r, f, F_HOUR, 1, 24, &hr))
        return 2;
    if (y != floor(y) || mo != floor(mo) || d != floor(d) || hr != floor(hr) ||
        !date_is_valid((int)y, (int)mo, (int)d))
        return bad(r, F_DAY, "is not a day of that month", f[F_DAY - 1]);
    h->year = (int)y, h->month = (int)mo, h->day = (int)d;
    /* hour N covers N-1:00 to N:00 local standard time; the sky of its middle */
    h->minute_of_day = ((int)hr - 1) * 60 + 30;
    h->aod550 = h->albedo = -1.0;
    h->sky_cover_tenths = -1;
    if (number(r, f, F_TOTAL_SKY_COVER, 0, 99, &x))
        return 2;
    if (!is_missing_code(x)) {
        if (x > 10 || x != floor(x))
            return bad(r, F_TOTAL_SKY_COVER, "is not tenths of sky 0-10 (99: missing)", f[F_TOTAL_SKY_COVER - 1]);
        h->sky_cover_tenths = (int)x;
    }
    if (number(r, f, F_AOD, 0, 99999, &x))
        return 2;
    if (!is_missing_code(x)) {
        if (x * EPW_AOD_TO_550 > 5.0) /* --aod550's range */
            return bad(r, F_AOD, "is not an optical depth in [0, 3.65] (.999: missing)", f[F_AOD - 1]);
        h->aod550 = x * EPW_AOD_TO_550;
    }
    if (number(r, f, F_ALBEDO, 0, 99999, &x))
        return 2;
    if (!is_missing_code(x)) {
        if (x > 1.0)
            return bad(r, F_ALBEDO, "is not an albedo in [0, 1] (999: missing)", f[F_ALBEDO - 1]);
        h->albedo = x;
    }
    return 0;
}

int epw_read(const char *path, epw_file *e, char *msg, size_t msg_size)
{
    memset(e, 0, sizeof *e);
    FILE *f = platform_fopen(path, "rb");
    if (!f) {
        snprintf(msg, msg_size, "--epw: cannot read '%s': %s", path, strerror(errno));
        return 2;
    }
    reader r = {path, 0, msg, msg_size};
    char line[4096];
    int code = 0, cap = 0;
    while (!code && fgets(line, sizeof line, f)) {
        r.line++;
        line[strcspn(line, "\r\n")] = '\0';
        if (r.line == 1)
            code = read_location(&r, line, e);
        else if (r.line > 8 && line[0]) {
            if (e->count == cap) {
                epw_hour *bigger = realloc(e->hours, (size_t)(cap += 1024) * sizeof *bigger);
                if (!bigger) {
                    snprintf(msg, msg_size, "out of memory");
                    code = 2;
                    break;
                }
                e->hours = bigger;
            }
            code = read_hour(&r, line, &e->hours[e->count]);
            e->count += !code;
        }
    }
    fclose(f);
    if (!code && r.line == 0) {
        snprintf(msg, msg_size, "%s: line 1: empty, an EPW starts with its LOCATION line", path);
        code = 2;
    } else if (!code && e->count == 0) {
        snprintf(msg, msg_size, "%s: line %d: no data lines after the 8 header lines", path, r.line + 1);
        code = 2;
    }
    return code;
}

void epw_free(epw_file *e)
{
    free(e->hours);
    memset(e, 0, sizeof *e);
}

#include "atmosphere/atmosphere_file.h"

#include "base/status.h"
#include "base/units.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILE_BYTES (64L << 20) /* far beyond any sensible description; refuses a wrong file early */
#define PATH_CHARS 96              /* a JSON path such as $.constituents[11].phase.values[3][181] */
#define MAX_TOP_KM 10000.0
#define MAX_RADIUS_KM 1e6
#define MAX_RHO (6.0 / 7.0)        /* depolarisation factor of natural light: 0 (spheres) to 6/7 */

/* Where a problem is reported: the file, the grid it is read for, the caller's error. */
typedef struct reader {
    const char *file;
    const spectral_grid *grid;
    fm_error *err;
} reader;

static fm_status bad(const reader *rd, const char *path, const char *fmt, ...) FM_PRINTF(3, 4);
static fm_status bad(const reader *rd, const char *path, const char *fmt, ...)
{
    char what[384];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return fm_fail_parameter(rd->err, "atmosphere_file", "%s: %s: %s", rd->file, path, what);
}

/* out = parent followed by the formatted suffix (".key", "[3]"), cut at PATH_CHARS. */
static void child_path(char *out, const char *parent, const char *fmt, ...) FM_PRINTF(3, 4);
static void child_path(char *out, const char *parent, const char *fmt, ...)
{
    size_t n = strlen(parent);
    if (n >= PATH_CHARS)
        n = PATH_CHARS - 1;
    memcpy(out, parent, n);
    out[n] = '\0';
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(out + n, PATH_CHARS - n, fmt, ap);
    va_end(ap);
}

static fm_status out_of_memory(const reader *rd)
{
    return fm_fail(rd->err, FM_ERR_OUT_OF_MEMORY, "out of memory while reading %s", rd->file);
}

static const char *type_name(const cJSON *n)
{
    if (cJSON_IsNumber(n))
        return "a number";
    if (cJSON_IsString(n))
        return "a string";
    if (cJSON_IsArray(n))
        return "an array";
    if (cJSON_IsObject(n))
        return "an object";
    if (cJSON_IsBool(n))
        return "a boolean";
    return "null";
}

/* ---- keys and scalars ------------------------------------------------------------------------- */

/* Fails on a key that is not in `allowed` (NULL-terminated: typos are caught) or that is repeated. */
static fm_status check_keys(const reader *rd, const cJSON *obj, const char *path, const char *const *allowed)
{
    for (const cJSON *it = obj->child; it; it = it->next) {
        int known = 0;
        for (const char *const *a = allowed; *a && !known; a++)
            known = strcmp(*a, it->string) == 0;
        if (!known) {
            char list[256] = "";
            for (const char *const *a = allowed; *a; a++) {
                size_t used = strlen(list);
                snprintf(list + used, sizeof list - used, "%s%s", a == allowed ? "" : ", ", *a);
            }
            return bad(rd, path, "unknown key \"%s\" (expected %s)", it->string, list);
        }
        for (const cJSON *prev = obj->child; prev != it; prev = prev->next)
            if (strcmp(prev->string, it->string) == 0)
                return bad(rd, path, "key \"%s\" appears twice", it->string);
    }
    return FM_OK;
}

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

static fm_status require_object(const reader *rd, const cJSON *node, const char *path)
{
    if (!cJSON_IsObject(node))
        return bad(rd, path, "must be an object, not %s", type_name(node));
    return FM_OK;
}

/* An interval of allowed values, printed as "[0, 1]", "(-1, 1)", "(0, 10000]". */
typedef struct interval {
    double lo, hi;
    int lo_open, hi_open;
} interval;

static const interval non_negative = {0.0, INFINITY, 0, 1};

static int in_interval(double v, interval r)
{
    return (r.lo_open ? v > r.lo : v >= r.lo) && (r.hi_open ? v < r.hi : v <= r.hi);
}

static fm_status check_value(const reader *rd, const char *path, double v, interval r)
{
    if (in_interval(v, r))
        return FM_OK;
    if (r.lo == 0.0 && isinf(r.hi))
        return bad(rd, path, "must be %s, not %g", r.lo_open ? "positive" : "non-negative", v);
    return bad(rd, path, "must be in %c%g, %g%c, not %g", r.lo_open ? '(' : '[', r.lo, r.hi, r.hi_open ? ')' : ']', v);
}

static fm_status get_number(const reader *rd, const cJSON *node, const char *path, interval r, double *out)
{
    if (!cJSON_IsNumber(node))
        return bad(rd, path, "must be a number, not %s", type_name(node));
    if (!isfinite(node->valuedouble))
        return bad(rd, path, "must be a finite number");
    *out = node->valuedouble;
    return check_value(rd, path, *out, r);
}

static fm_status required_number(const reader *rd, const cJSON *obj, const char *path, const char *key, interval r,
                                 double *out)
{
    char p[PATH_CHARS];
    child_path(p, path, ".%s", key);
    const cJSON *n = member(obj, key);
    if (!n)
        return bad(rd, path, "missing \"%s\"", key);
    return get_number(rd, n, p, r, out);
}

/* An array of at least min_count numbers in r; *out is allocated (free it). */
static fm_status get_numbers(const reader *rd, const cJSON *node, const char *path, int min_count, interval r,
                             double **out, int *count)
{
    *out = NULL;
    if (!cJSON_IsArray(node))
        return bad(rd, path, "must be an array of numbers, not %s", type_name(node));
    int n = cJSON_GetArraySize(node);
    if (n < min_count)
        return bad(rd, path, "needs at least %d value%s, has %d", min_count, min_count == 1 ? "" : "s", n);
    double *v = malloc(sizeof(double) * (size_t)n);
    if (!v)
        return out_of_memory(rd);
    int i = 0;
    for (const cJSON *it = node->child; it; it = it->next, i++) {
        char p[PATH_CHARS];
        child_path(p, path, "[%d]", i);
        fm_status s = get_number(rd, it, p, r, &v[i]);
        if (s) {
            free(v);
            return s;
        }
    }
    *out = v;
    *count = n;
    return FM_OK;
}

static fm_status check_ascending(const reader *rd, const char *path, const double *x, int n)
{
    for (int i = 1; i < n; i++)
        if (!(x[i] > x[i - 1])) {
            char p[PATH_CHARS];
            child_path(p, path, "[%d]", i);
            return bad(rd, p, "must be greater than the value before it (%g), not %g", x[i - 1], x[i]);
        }
    return FM_OK;
}

/* Linear interpolation in ascending x[], held constant beyond the ends. */
static double interpolate_clamped(const double *x, const double *y, int n, double at)
{
    if (n == 1 || at <= x[0])
        return y[0];
    if (at >= x[n - 1])
        return y[n - 1];
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (x[mid] <= at)
            lo = mid;
        else
            hi = mid;
    }
    double t = (at - x[lo]) / (x[hi] - x[lo]);
    return y[lo] + (y[hi] - y[lo]) * t;
}

/* ---- spectral quantities: a number, or {"wavelengths_nm": [...], "values": [...]} ------------- */

typedef struct spectral {
    int count;         /* 1: constant */
    double *lambda_nm; /* [count] ascending, NULL for a constant */
    double *value;     /* [count] */
    char path[PATH_CHARS];
} spectral;

static void spectral_free(spectral *s)
{
    free(s->lambda_nm);
    free(s->value);
    s->lambda_nm = s->value = NULL;
    s->count = 0;
}

static const char *const spectral_keys[] = {"wavelengths_nm", "values", NULL};

static fm_status read_spectral(const reader *rd, const cJSON *node, const char *path, interval r, spectral *s)
{
    memset(s, 0, sizeof *s);
    snprintf(s->path, sizeof s->path, "%s", path);
    if (cJSON_IsNumber(node)) {
        s->value = malloc(sizeof(double));
        if (!s->value)
            return out_of_memory(rd);
        s->count = 1;
        fm_status st = get_number(rd, node, path, r, &s->value[0]);
        if (st)
            spectral_free(s);
        return st;
    }
    if (!cJSON_IsObject(node))
        return bad(rd, path, "must be a number or an object with \"wavelengths_nm\" and \"values\", not %s",
                   type_name(node));
    fm_status st;
    if ((st = check_keys(rd, node, path, spectral_keys)))
        return st;
    const cJSON *wl = member(node, "wavelengths_nm"), *val = member(node, "values");
    if (!wl || !val)
        return bad(rd, path, "missing \"%s\"", wl ? "values" : "wavelengths_nm");
    char pw[PATH_CHARS], pv[PATH_CHARS];
    child_path(pw, path, ".wavelengths_nm");
    child_path(pv, path, ".values");
    int nw = 0, nv = 0;
    const interval positive = {0.0, INFINITY, 1, 1};
    if ((st = get_numbers(rd, wl, pw, 1, positive, &s->lambda_nm, &nw)) ||
        (st = check_ascending(rd, pw, s->lambda_nm, nw)) || (st = get_numbers(rd, val, pv, 1, r, &s->value, &nv))) {
        spectral_free(s);
        return st;
    }
    if (nv != nw) {
        spectral_free(s);
        return bad(rd, path, "has %d wavelengths but %d values", nw, nv);
    }
    s->count = nw;
    return FM_OK;
}

/* The quantity at every grid wavelength; a grid wavelength outside the listed range is an error
 * (no silent extrapolation).  owner names the constituent (or NULL). */
static fm_status spectral_on_grid(const reader *rd, const spectral *s, const char *owner, double *out)
{
    const spectral_grid *g = rd->grid;
    if (s->count > 1) {
        double first = s->lambda_nm[0], last = s->lambda_nm[s->count - 1];
        double need_lo = g->lambda_nm[0], need_hi = g->lambda_nm[g->count - 1];
        if (need_lo < first || need_hi > last) {
            char need[64];
            if (g->count == 1)
                snprintf(need, sizeof need, "%g nm", need_lo);
            else
                snprintf(need, sizeof need, "%g-%g nm", need_lo, need_hi);
            return bad(rd, s->path, "given for %g-%g nm%s%s%s, but the render needs %s", first, last,
                       owner ? " (constituent \"" : "", owner ? owner : "", owner ? "\")" : "", need);
        }
    }
    for (int k = 0; k < g->count; k++)
        out[k] = s->count == 1 ? s->value[0] : interpolate_clamped(s->lambda_nm, s->value, s->count, g->lambda_nm[k]);
    return FM_OK;
}

/* An optional spectral member: absent gives fallback at every grid wavelength. */
static fm_status optional_spectral(const reader *rd, const cJSON *obj, const char *path, const char *key, interval r,
                                   const char *owner, double fallback, double *out, int *present)
{
    const cJSON *n = member(obj, key);
    if (present)
        *present = n != NULL;
    if (!n) {
        for (int k = 0; k < rd->grid->count; k++)
            out[k] = fallback;
        return FM_OK;
    }
    char p[PATH_CHARS];
    child_path(p, path, ".%s", key);
    spectral s;
    fm_status st = read_spectral(rd, n, p, r, &s);
    if (!st)
        st = spectral_on_grid(rd, &s, owner, out);
    spectral_free(&s);
    return st;
}

/* ---- density profiles ------------------------------------------------------------------------- */

typedef struct tabulated_profile {
    const double *altitude_m, *value;
    int count;
} tabulated_profile;

static double exponential_density(void *ctx, double altitude_m)
{
    return exp(-altitude_m / *(const double *)ctx);
}

static double tabulated_density(void *ctx, double altitude_m)
{
    const tabulated_profile *t = ctx;
    return interpolate_clamped(t->altitude_m, t->value, t->count, altitude_m);
}

static const char *const profile_keys[] = {"type", "scale_height_km", "altitudes_km", "values", NULL};

static fm_status read_profile(const reader *rd, const cJSON *node, const char *path, double top_m,
                              density_profile *out)
{
    fm_status st;
    if ((st = require_object(rd, node, path)) || (st = check_keys(rd, node, path, profile_keys)))
        return st;
    const cJSON *type = member(node, "type");
    char p[PATH_CHARS];
    child_path(p, path, ".type");
    if (!type)
        return bad(rd, path, "missing \"type\" (\"exponential\" or \"tabulated\")");
    if (!cJSON_IsString(type))
        return bad(rd, p, "must be a string, not %s", type_name(type));
    if (strcmp(type->valuestring, "exponential") == 0) {
        if (member(node, "altitudes_km") || member(node, "values"))
            return bad(rd, path, "an exponential profile takes only \"scale_height_km\"");
        double h_km;
        const interval positive = {0.0, INFINITY, 1, 1};
        if ((st = required_number(rd, node, path, "scale_height_km", positive, &h_km)))
            return st;
        double h_m = h_km * FM_KM;
        if (profile_sample(out, exponential_density, &h_m, top_m, FM_PROFILE_SPACING_M))
            return out_of_memory(rd);
        return FM_OK;
    }
    if (strcmp(type->valuestring, "tabulated") == 0) {
        if (member(node, "scale_height_km"))
            return bad(rd, path, "a tabulated profile takes \"altitudes_km\" and \"values\", not \"scale_height_km\"");
        const cJSON *alt = member(node, "altitudes_km"), *val = member(node, "values");
        if (!alt || !val)
            return bad(rd, path, "missing \"%s\"", alt ? "values" : "altitudes_km");
        char pa[PATH_CHARS], pv[PATH_CHARS];
        child_path(pa, path, ".altitudes_km");
        child_path(pv, path, ".values");
        double *a = NULL, *v = NULL;
        int na = 0, nv = 0;
        const interval any = {-INFINITY, INFINITY, 1, 1};
        if (!(st = get_numbers(rd, alt, pa, 2, any, &a, &na)) && !(st = check_ascending(rd, pa, a, na)) &&
            !(st = get_numbers(rd, val, pv, 2, non_negative, &v, &nv))) {
            if (nv != na)
                st = bad(rd, path, "has %d altitudes but %d values", na, nv);
            else if (a[0] > 0.0 || a[na - 1] * FM_KM < top_m)
                st = bad(rd, pa, "must cover the atmosphere from 0 to %g km, covers %g to %g km", top_m / FM_KM, a[0],
                         a[na - 1]);
        }
        if (!st) {
            for (int i = 0; i < na; i++)
                a[i] *= FM_KM;
            tabulated_profile t = {a, v, na};
            if (profile_sample(out, tabulated_density, &t, top_m, FM_PROFILE_SPACING_M))
                st = out_of_memory(rd);
        }
        free(a);
        free(v);
        return st;
    }
    return bad(rd, p, "\"%s\" is not a profile type (\"exponential\" or \"tabulated\")", type->valuestring);
}

/* ---- phase functions -------------------------------------------------------------------------- */

static const char *const phase_keys[] = {"type", "depolarization", "g", "angles_deg", "wavelengths_nm", "values",
                                         NULL};

/* Fails when obj has any of the keys listed (they belong to another phase type). */
static fm_status refuse_keys(const reader *rd, const cJSON *obj, const char *path, const char *type,
                             const char *const *keys)
{
    for (const char *const *k = keys; *k; k++)
        if (member(obj, *k))
            return bad(rd, path, "\"%s\" does not apply to a %s phase function", *k, type);
    return FM_OK;
}

/* Normalises a row tabulated at mu[] (descending) so its piecewise-linear integral over the sphere
 * is 1; fails (returns 0) when the integral is 0. */
static int normalise_row(const double *mu, double *row, int n)
{
    double integral = 0.0;
    for (int j = 0; j + 1 < n; j++)
        integral += 0.5 * (row[j] + row[j + 1]) * (mu[j] - mu[j + 1]);
    integral *= 2.0 * FM_PI;
    if (!(integral > 0.0))
        return 0;
    for (int j = 0; j < n; j++)
        row[j] /= integral;
    return 1;
}

static fm_status read_tabulated_phase(const reader *rd, const cJSON *node, const char *path, const char *owner,
                                      phase_function *out)
{
    fm_status st;
    const char *const other[] = {"depolarization", "g", NULL};
    if ((st = refuse_keys(rd, node, path, "tabulated", other)))
        return st;
    const cJSON *ang = member(node, "angles_deg"), *val = member(node, "values"), *wl = member(node, "wavelengths_nm");
    if (!ang || !val)
        return bad(rd, path, "missing \"%s\"", ang ? "values" : "angles_deg");
    char pa[PATH_CHARS], pv[PATH_CHARS], pw[PATH_CHARS];
    child_path(pa, path, ".angles_deg");
    child_path(pv, path, ".values");
    child_path(pw, path, ".wavelengths_nm");
    double *theta = NULL, *mu = NULL, *lambda = NULL, *rows = NULL, *grid_values = NULL;
    int n = 0, m = 1;
    const interval angle = {0.0, 180.0, 0, 0}, positive = {0.0, INFINITY, 1, 1};
    if ((st = get_numbers(rd, ang, pa, 2, angle, &theta, &n)) || (st = check_ascending(rd, pa, theta, n)))
        goto done;
    if (theta[0] != 0.0 || theta[n - 1] != 180.0) {
        st = bad(rd, pa, "must run from 0 to 180 degrees, runs from %g to %g", theta[0], theta[n - 1]);
        goto done;
    }
    /* one row of values, or one row per listed wavelength */
    int per_wavelength = cJSON_IsArray(val) && val->child && cJSON_IsArray(val->child);
    if (per_wavelength != (wl != NULL)) {
        st = bad(rd, path,
                 wl ? "with \"wavelengths_nm\", \"values\" must be an array of rows, one per wavelength"
                    : "\"values\" given per wavelength needs \"wavelengths_nm\"");
        goto done;
    }
    if (wl && ((st = get_numbers(rd, wl, pw, 1, positive, &lambda, &m)) || (st = check_ascending(rd, pw, lambda, m))))
        goto done;
    if (per_wavelength && cJSON_GetArraySize(val) != m) {
        st = bad(rd, path, "has %d wavelengths but %d rows of values", m, cJSON_GetArraySize(val));
        goto done;
    }
    mu = malloc(sizeof(double) * (size_t)n);
    rows = malloc(sizeof(double) * (size_t)n * (size_t)m);
    grid_values = malloc(sizeof(double) * (size_t)n * (size_t)rd->grid->count);
    if (!mu || !rows || !grid_values) {
        st = out_of_memory(rd);
        goto done;
    }
    for (int j = 0; j < n; j++)
        mu[j] = cos(theta[j] * FM_DEG);
    mu[0] = 1.0;
    mu[n - 1] = -1.0;
    const cJSON *row = per_wavelength ? val->child : val;
    for (int i = 0; i < m; i++, row = row ? row->next : NULL) {
        char pr[PATH_CHARS];
        if (per_wavelength)
            child_path(pr, pv, "[%d]", i);
        else
            child_path(pr, pv, "%s", "");
        double *v = NULL;
        int nv = 0;
        if ((st = get_numbers(rd, row, pr, 2, non_negative, &v, &nv)))
            goto done;
        if (nv != n) {
            free(v);
            st = bad(rd, pr, "has %d values for %d angles", nv, n);
            goto done;
        }
        memcpy(rows + (size_t)i * n, v, sizeof(double) * (size_t)n);
        free(v);
        if (!normalise_row(mu, rows + (size_t)i * n, n)) {
            st = bad(rd, pr, "integrates to 0 over the sphere");
            goto done;
        }
    }
    /* rows (each normalised) interpolated linearly in wavelength onto the grid */
    const spectral_grid *g = rd->grid;
    if (m > 1 && (g->lambda_nm[0] < lambda[0] || g->lambda_nm[g->count - 1] > lambda[m - 1])) {
        st = bad(rd, pw, "given for %g-%g nm (constituent \"%s\"), but the render needs %g-%g nm", lambda[0],
                 lambda[m - 1], owner, g->lambda_nm[0], g->lambda_nm[g->count - 1]);
        goto done;
    }
    for (int k = 0; k < g->count; k++) {
        int i0 = 0, i1 = 0;
        double t = 0.0;
        if (m > 1) {
            while (i0 < m - 2 && lambda[i0 + 1] <= g->lambda_nm[k])
                i0++;
            i1 = i0 + 1;
            t = (g->lambda_nm[k] - lambda[i0]) / (lambda[i1] - lambda[i0]);
        }
        for (int j = 0; j < n; j++)
            grid_values[(size_t)k * n + j] = (1.0 - t) * rows[(size_t)i0 * n + j] + t * rows[(size_t)i1 * n + j];
    }
    for (int j = 0; j < n; j++)
        theta[j] *= FM_DEG;
    theta[n - 1] = FM_PI;
    fm_error inner = {0};
    st = phase_init_tabulated(out, g->count, n, theta, grid_values, &inner);
    if (st == FM_ERR_INVALID_ARGUMENT)
        st = bad(rd, path, "%s", inner.message);
    else if (st)
        st = out_of_memory(rd);
done:
    free(theta);
    free(mu);
    free(lambda);
    free(rows);
    free(grid_values);
    return st;
}

static fm_status read_phase(const reader *rd, const cJSON *node, const char *path, const char *owner,
                            phase_function *out)
{
    fm_status st;
    if ((st = require_object(rd, node, path)) || (st = check_keys(rd, node, path, phase_keys)))
        return st;
    const cJSON *type = member(node, "type");
    char p[PATH_CHARS];
    child_path(p, path, ".type");
    if (!type)
        return bad(rd, path, "missing \"type\" (\"rayleigh\", \"henyey-greenstein\" or \"tabulated\")");
    if (!cJSON_IsString(type))
        return bad(rd, p, "must be a string, not %s", type_name(type));
    const int K = rd->grid->count;
    if (strcmp(type->valuestring, "rayleigh") == 0) {
        const char *const other[] = {"g", "angles_deg", "wavelengths_nm", "values", NULL};
        const interval rho_range = {0.0, MAX_RHO, 0, 0};
        double rho[FM_MAX_WAVELENGTHS];
        if ((st = refuse_keys(rd, node, path, "Rayleigh", other)) ||
            (st = optional_spectral(rd, node, path, "depolarization", rho_range, owner, 0.0, rho, NULL)))
            return st;
        out->kind = PHASE_RAYLEIGH;
        for (int k = 0; k < K; k++)
            out->param[k] = rho[k] / (2.0 - rho[k]); /* phase_rayleigh.h's gamma */
        return FM_OK;
    }
    if (strcmp(type->valuestring, "henyey-greenstein") == 0) {
        const char *const other[] = {"depolarization", "angles_deg", "wavelengths_nm", "values", NULL};
        const interval g_range = {-1.0, 1.0, 1, 1};
        int present = 0;
        if ((st = refuse_keys(rd, node, path, "Henyey-Greenstein", other)) ||
            (st = optional_spectral(rd, node, path, "g", g_range, owner, 0.0, out->param, &present)))
            return st;
        if (!present)
            return bad(rd, path, "missing \"g\" (the asymmetry parameter, in (-1, 1))");
        out->kind = PHASE_HENYEY_GREENSTEIN;
        return FM_OK;
    }
    if (strcmp(type->valuestring, "tabulated") == 0)
        return read_tabulated_phase(rd, node, path, owner, out);
    return bad(rd, p, "\"%s\" is not a phase function type (\"rayleigh\", \"henyey-greenstein\" or \"tabulated\")",
               type->valuestring);
}

/* ---- constituents ----------------------------------------------------------------------------- */

static const char *const constituent_keys[] = {"name",       "profile", "scattering", "absorption", "extinction",
                                               "single_scattering_albedo", "phase", NULL};

static fm_status read_constituent(const reader *rd, const cJSON *node, const char *path, double top_m, species *sp,
                                  char *name, size_t name_size)
{
    fm_status st;
    if ((st = require_object(rd, node, path)) || (st = check_keys(rd, node, path, constituent_keys)))
        return st;
    const cJSON *nm = member(node, "name");
    if (nm && !cJSON_IsString(nm)) {
        char p[PATH_CHARS];
        child_path(p, path, ".name");
        return bad(rd, p, "must be a string, not %s", type_name(nm));
    }
    if (nm)
        snprintf(name, name_size, "%s", nm->valuestring);
    sp->name = name;

    /* coefficients: scattering + absorption, or extinction + single-scattering albedo */
    const int K = rd->grid->count;
    int has_ext = member(node, "extinction") != NULL, has_ssa = member(node, "single_scattering_albedo") != NULL;
    if (has_ext || has_ssa) {
        if (member(node, "scattering") || member(node, "absorption"))
            return bad(rd, path, "give either \"scattering\" and \"absorption\" or \"extinction\" and "
                                 "\"single_scattering_albedo\", not both");
        if (!has_ext || !has_ssa)
            return bad(rd, path, "\"%s\" needs \"%s\"", has_ext ? "extinction" : "single_scattering_albedo",
                       has_ext ? "single_scattering_albedo" : "extinction");
        double ext[FM_MAX_WAVELENGTHS], ssa[FM_MAX_WAVELENGTHS];
        const interval unit = {0.0, 1.0, 0, 0};
        if ((st = optional_spectral(rd, node, path, "extinction", non_negative, name, 0.0, ext, NULL)) ||
            (st = optional_spectral(rd, node, path, "single_scattering_albedo", unit, name, 0.0, ssa, NULL)))
            return st;
        for (int k = 0; k < K; k++) {
            sp->sigma_s[k] = ext[k] * ssa[k];
            sp->sigma_a[k] = ext[k] - sp->sigma_s[k];
        }
    } else {
        int has_s = 0, has_a = 0;
        if ((st = optional_spectral(rd, node, path, "scattering", non_negative, name, 0.0, sp->sigma_s, &has_s)) ||
            (st = optional_spectral(rd, node, path, "absorption", non_negative, name, 0.0, sp->sigma_a, &has_a)))
            return st;
        if (!has_s && !has_a)
            return bad(rd, path, "missing coefficients: \"scattering\" and/or \"absorption\", or \"extinction\" and "
                                 "\"single_scattering_albedo\" (m^-1)");
    }

    const cJSON *phase = member(node, "phase");
    if (phase) {
        char p[PATH_CHARS];
        child_path(p, path, ".phase");
        if ((st = read_phase(rd, phase, p, name, &sp->phase)))
            return st;
    } else {
        for (int k = 0; k < K; k++)
            if (sp->sigma_s[k] > 0.0)
                return bad(rd, path, "missing \"phase\": the constituent scatters");
        sp->phase.kind = PHASE_NONE;
    }

    const cJSON *profile = member(node, "profile");
    if (!profile)
        return bad(rd, path, "missing \"profile\"");
    char p[PATH_CHARS];
    child_path(p, path, ".profile");
    return read_profile(rd, profile, p, top_m, &sp->profile);
}

/* ---- the file --------------------------------------------------------------------------------- */

static fm_status read_text(const reader *rd, char **out, size_t *size)
{
    *out = NULL;
    FILE *f = fopen(rd->file, "rb");
    if (!f)
        return fm_fail_parameter(rd->err, "atmosphere_file", "%s: cannot open: %s", rd->file, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    fm_status st = FM_OK;
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap)
            break;
        if ((long)cap >= MAX_FILE_BYTES) {
            st = fm_fail_parameter(rd->err, "atmosphere_file", "%s: larger than %ld MiB: not an atmosphere file",
                                   rd->file, MAX_FILE_BYTES >> 20);
            break;
        }
        cap *= 2;
        char *grown = realloc(buf, cap + 1);
        if (!grown)
            free(buf);
        buf = grown;
    }
    if (!buf)
        st = out_of_memory(rd);
    else if (!st && ferror(f))
        st = fm_fail_parameter(rd->err, "atmosphere_file", "%s: cannot read: %s", rd->file, strerror(errno));
    fclose(f);
    if (st) {
        free(buf);
        return st;
    }
    buf[n] = '\0';
    *out = buf;
    *size = n;
    return FM_OK;
}

static fm_status syntax_error(const reader *rd, const char *text, size_t size, const char *at)
{
    size_t offset = at && at >= text && at <= text + size ? (size_t)(at - text) : size;
    /* cJSON sometimes points just past the offending character (e.g. after a stray comma): on
     * whitespace, report the last character before it */
    while (offset < size && offset > 0 && isspace((unsigned char)text[offset]))
        offset--;
    int line = 1, column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n')
            line++, column = 1;
        else
            column++;
    }
    if (offset >= size)
        return fm_fail_parameter(rd->err, "atmosphere_file", "%s:%d:%d: JSON syntax error: unexpected end of file",
                                 rd->file, line, column);
    int shown = 0; /* up to 12 characters of the line from there */
    while (shown < 12 && offset + shown < size && text[offset + shown] != '\n' && text[offset + shown] != '\r')
        shown++;
    return fm_fail_parameter(rd->err, "atmosphere_file", "%s:%d:%d: JSON syntax error at '%.*s'", rd->file, line,
                             column, shown, text + offset);
}

static double file_solar(const void *ctx, double lambda_nm)
{
    const spectral *s = ctx;
    return s->count == 1 ? s->value[0] : interpolate_clamped(s->lambda_nm, s->value, s->count, lambda_nm);
}

static const char *const top_keys[] = {"name",          "description",      "planet_radius_km", "top_altitude_km",
                                       "ground_albedo", "solar_irradiance", "constituents",     NULL};

static fm_status build(const reader *rd, const cJSON *root, atmosphere *atm, double solar_scale, double ground_albedo)
{
    fm_status st;
    if ((st = require_object(rd, root, "$")) || (st = check_keys(rd, root, "$", top_keys)))
        return st;
    for (int i = 0; i < 2; i++) {
        const char *key = i ? "description" : "name";
        const cJSON *n = member(root, key);
        if (n && !cJSON_IsString(n)) {
            char p[PATH_CHARS];
            snprintf(p, sizeof p, "$.%s", key);
            return bad(rd, p, "must be a string, not %s", type_name(n));
        }
    }
    const interval radius = {0.0, MAX_RADIUS_KM, 1, 0}, top = {0.0, MAX_TOP_KM, 1, 0}, unit = {0.0, 1.0, 0, 0};
    double radius_km, top_km;
    if ((st = required_number(rd, root, "$", "planet_radius_km", radius, &radius_km)) ||
        (st = required_number(rd, root, "$", "top_altitude_km", top, &top_km)))
        return st;
    atm->bottom_radius_m = radius_km * FM_KM;
    atm->top_radius_m = (radius_km + top_km) * FM_KM;
    double top_m = top_km * FM_KM;

    if ((st = optional_spectral(rd, root, "$", "ground_albedo", unit, NULL, ground_albedo, atm->ground_albedo, NULL)))
        return st;

    const cJSON *solar = member(root, "solar_irradiance");
    if (solar) {
        spectral s;
        if ((st = read_spectral(rd, solar, "$.solar_irradiance", non_negative, &s)))
            return st;
        double check[FM_MAX_WAVELENGTHS];
        if (!(st = spectral_on_grid(rd, &s, NULL, check))) {
            spectral_grid_set_solar(&atm->grid, file_solar, &s);
            for (int k = 0; k < atm->grid.count; k++)
                atm->grid.solar_irradiance[k] *= solar_scale;
        }
        spectral_free(&s);
        if (st)
            return st;
    }

    const cJSON *list = member(root, "constituents");
    if (!list)
        return bad(rd, "$", "missing \"constituents\"");
    if (!cJSON_IsArray(list))
        return bad(rd, "$.constituents", "must be an array, not %s", type_name(list));
    int count = cJSON_GetArraySize(list);
    if (count < 1 || count > FM_MAX_SPECIES)
        return bad(rd, "$.constituents", "must hold 1 to %d constituents, holds %d", FM_MAX_SPECIES, count);
    int i = 0;
    for (const cJSON *it = list->child; it; it = it->next, i++) {
        char p[PATH_CHARS];
        snprintf(p, sizeof p, "$.constituents[%d]", i);
        snprintf(atm->species_names[i], sizeof atm->species_names[i], "constituent %d", i);
        atm->species_count = i + 1; /* so that atmosphere_free releases what was built */
        if ((st = read_constituent(rd, it, p, top_m, &atm->species[i], atm->species_names[i],
                                   sizeof atm->species_names[i])))
            return st;
    }
    /* scatterers first (atmosphere.h), keeping the file's order otherwise */
    species sorted[FM_MAX_SPECIES];
    int n = 0;
    for (int pass = 0; pass < 2; pass++)
        for (int c = 0; c < count; c++)
            if ((atm->species[c].phase.kind != PHASE_NONE) == (pass == 0))
                sorted[n++] = atm->species[c];
    for (int c = 0; c < count; c++) {
        if (sorted[c].phase.kind != PHASE_NONE)
            atm->scattering_count = c + 1;
        atm->species[c] = sorted[c];
    }
    return FM_OK;
}

fm_status atmosphere_init_from_file(atmosphere *atm, const char *path, const spectral_grid *grid, double solar_scale,
                                    double ground_albedo, fm_error *err)
{
    memset(atm, 0, sizeof *atm);
    atm->grid = *grid;
    reader rd = {path, &atm->grid, err};
    char *text = NULL;
    size_t size = 0;
    fm_status st = read_text(&rd, &text, &size);
    if (st)
        return st;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, size + 1, &end, 1) /* with the NUL */;
    if (!root) {
        st = syntax_error(&rd, text, size, end);
        free(text);
        return st;
    }
    st = build(&rd, root, atm, solar_scale, ground_albedo);
    cJSON_Delete(root);
    free(text);
    if (st) {
        atmosphere_free(atm);
        return st;
    }
    atmosphere_update_majorants(atm);
    return FM_OK;
}

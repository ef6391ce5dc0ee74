#include "atmosphere/atmosphere_file.h"

#include "base/json_file.h"
#include "base/status.h"
#include "base/units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Physically meaningful ranges (docs/atmosphere-file.md): outside them the tables' arithmetic loses
 * its meaning (a planet of 1e-300 km divides by zero) long before any real atmosphere is refused. */
#define MIN_RADIUS_KM 100.0  /* below the smallest bodies with an atmosphere (Pluto 1188 km) */
#define MAX_RADIUS_KM 1e6    /* above the Sun (696000 km) */
#define MIN_TOP_KM 1.0       /* 20 steps of the 50 m profile grid */
#define MAX_TOP_KM 10000.0
#define MIN_SCALE_HEIGHT_KM 0.1 /* two steps of the profile grid: a thinner layer would be smeared */
#define MAX_SCALE_HEIGHT_KM 1e4
#define MAX_ALTITUDE_KM 1e5     /* a tabulated profile's altitudes, within +-this */
#define MAX_PROFILE 1e3         /* a tabulated profile's values: a thousand times its reference density */
#define MAX_COEFFICIENT 1.0     /* m^-1: fog and the thickest clouds reach about 0.15 */
#define MAX_RHO (6.0 / 7.0)        /* depolarisation factor of natural light: 0 (spheres) to 6/7 */

/* The file's reader and the grid its spectral quantities are read for. */
typedef struct reader {
    json_reader json;
    const spectral_grid *grid;
} reader;

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(obj, key);
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
    char path[JSON_PATH_CHARS];
} spectral;

static void spectral_free(spectral *s)
{
    free(s->lambda_nm);
    free(s->value);
    s->lambda_nm = s->value = NULL;
    s->count = 0;
}

static const char *const spectral_keys[] = {"wavelengths_nm", "values", NULL};

static fm_status read_spectral(const reader *rd, const cJSON *node, const char *path, json_interval r, spectral *s)
{
    memset(s, 0, sizeof *s);
    snprintf(s->path, sizeof s->path, "%s", path);
    if (cJSON_IsNumber(node)) {
        s->value = malloc(sizeof(double));
        if (!s->value)
            return json_out_of_memory(&rd->json);
        s->count = 1;
        fm_status st = json_get_number(&rd->json, node, path, r, &s->value[0]);
        if (st)
            spectral_free(s);
        return st;
    }
    if (!cJSON_IsObject(node))
        return json_bad(&rd->json, path, "must be a number or an object with \"wavelengths_nm\" and \"values\", not %s",
                        json_type_name(node));
    fm_status st;
    if ((st = json_check_keys(&rd->json, node, path, spectral_keys)))
        return st;
    const cJSON *wl = member(node, "wavelengths_nm"), *val = member(node, "values");
    if (!wl || !val)
        return json_bad(&rd->json, path, "missing \"%s\"", wl ? "values" : "wavelengths_nm");
    char pw[JSON_PATH_CHARS], pv[JSON_PATH_CHARS];
    json_child_path(pw, path, ".wavelengths_nm");
    json_child_path(pv, path, ".values");
    int nw = 0, nv = 0;
    if ((st = json_get_numbers(&rd->json, wl, pw, 1, json_positive, &s->lambda_nm, &nw)) ||
        (st = json_check_ascending(&rd->json, pw, s->lambda_nm, nw)) ||
        (st = json_get_numbers(&rd->json, val, pv, 1, r, &s->value, &nv))) {
        spectral_free(s);
        return st;
    }
    if (nv != nw) {
        spectral_free(s);
        return json_bad(&rd->json, path, "has %d wavelengths but %d values", nw, nv);
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
            return json_bad(&rd->json, s->path, "given for %g-%g nm%s%s%s, but the render needs %s", first, last,
                            owner ? " (constituent \"" : "", owner ? owner : "", owner ? "\")" : "", need);
        }
    }
    for (int k = 0; k < g->count; k++)
        out[k] = s->count == 1 ? s->value[0] : interpolate_clamped(s->lambda_nm, s->value, s->count, g->lambda_nm[k]);
    return FM_OK;
}

/* An optional spectral member: absent gives fallback at every grid wavelength. */
static fm_status optional_spectral(const reader *rd, const cJSON *obj, const char *path, const char *key,
                                   json_interval r, const char *owner, double fallback, double *out, int *present)
{
    const cJSON *n = member(obj, key);
    if (present)
        *present = n != NULL;
    if (!n) {
        for (int k = 0; k < rd->grid->count; k++)
            out[k] = fallback;
        return FM_OK;
    }
    char p[JSON_PATH_CHARS];
    json_child_path(p, path, ".%s", key);
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
    if ((st = json_require_object(&rd->json, node, path)) ||
        (st = json_check_keys(&rd->json, node, path, profile_keys)))
        return st;
    const cJSON *type = member(node, "type");
    char p[JSON_PATH_CHARS];
    json_child_path(p, path, ".type");
    if (!type)
        return json_bad(&rd->json, path, "missing \"type\" (\"exponential\" or \"tabulated\")");
    if (!cJSON_IsString(type))
        return json_bad(&rd->json, p, "must be a string, not %s", json_type_name(type));
    if (strcmp(type->valuestring, "exponential") == 0) {
        if (member(node, "altitudes_km") || member(node, "values"))
            return json_bad(&rd->json, path, "an exponential profile takes only \"scale_height_km\"");
        double h_km;
        const json_interval scale = {MIN_SCALE_HEIGHT_KM, MAX_SCALE_HEIGHT_KM, 0, 0};
        if ((st = json_required_number(&rd->json, node, path, "scale_height_km", scale, &h_km)))
            return st;
        double h_m = h_km * FM_KM;
        if (profile_sample(out, exponential_density, &h_m, top_m, FM_PROFILE_SPACING_M))
            return json_out_of_memory(&rd->json);
        return FM_OK;
    }
    if (strcmp(type->valuestring, "tabulated") == 0) {
        if (member(node, "scale_height_km"))
            return json_bad(&rd->json, path,
                            "a tabulated profile takes \"altitudes_km\" and \"values\", not \"scale_height_km\"");
        const cJSON *alt = member(node, "altitudes_km"), *val = member(node, "values");
        if (!alt || !val)
            return json_bad(&rd->json, path, "missing \"%s\"", alt ? "values" : "altitudes_km");
        char pa[JSON_PATH_CHARS], pv[JSON_PATH_CHARS];
        json_child_path(pa, path, ".altitudes_km");
        json_child_path(pv, path, ".values");
        double *a = NULL, *v = NULL;
        int na = 0, nv = 0;
        const json_interval altitude = {-MAX_ALTITUDE_KM, MAX_ALTITUDE_KM, 0, 0}, value = {0.0, MAX_PROFILE, 0, 0};
        if (!(st = json_get_numbers(&rd->json, alt, pa, 2, altitude, &a, &na)) &&
            !(st = json_check_ascending(&rd->json, pa, a, na)) &&
            !(st = json_get_numbers(&rd->json, val, pv, 2, value, &v, &nv))) {
            if (nv != na)
                st = json_bad(&rd->json, path, "has %d altitudes but %d values", na, nv);
            else if (a[0] > 0.0 || a[na - 1] * FM_KM < top_m)
                st = json_bad(&rd->json, pa, "must cover the atmosphere from 0 to %g km, covers %g to %g km",
                              top_m / FM_KM, a[0], a[na - 1]);
        }
        if (!st) {
            for (int i = 0; i < na; i++)
                a[i] *= FM_KM;
            tabulated_profile t = {a, v, na};
            if (profile_sample(out, tabulated_density, &t, top_m, FM_PROFILE_SPACING_M))
                st = json_out_of_memory(&rd->json);
        }
        free(a);
        free(v);
        return st;
    }
    return json_bad(&rd->json, p, "\"%s\" is not a profile type (\"exponential\" or \"tabulated\")", type->valuestring);
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
            return json_bad(&rd->json, path, "\"%s\" does not apply to a %s phase function", *k, type);
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
        return json_bad(&rd->json, path, "missing \"%s\"", ang ? "values" : "angles_deg");
    char pa[JSON_PATH_CHARS], pv[JSON_PATH_CHARS], pw[JSON_PATH_CHARS];
    json_child_path(pa, path, ".angles_deg");
    json_child_path(pv, path, ".values");
    json_child_path(pw, path, ".wavelengths_nm");
    double *theta = NULL, *mu = NULL, *lambda = NULL, *rows = NULL, *grid_values = NULL;
    int n = 0, m = 1;
    const json_interval angle = {0.0, 180.0, 0, 0};
    if ((st = json_get_numbers(&rd->json, ang, pa, 2, angle, &theta, &n)) ||
        (st = json_check_ascending(&rd->json, pa, theta, n)))
        goto done;
    if (theta[0] != 0.0 || theta[n - 1] != 180.0) {
        st = json_bad(&rd->json, pa, "must run from 0 to 180 degrees, runs from %g to %g", theta[0], theta[n - 1]);
        goto done;
    }
    /* one row of values, or one row per listed wavelength */
    int per_wavelength = cJSON_IsArray(val) && val->child && cJSON_IsArray(val->child);
    if (per_wavelength != (wl != NULL)) {
        st = json_bad(&rd->json, path,
                      wl ? "with \"wavelengths_nm\", \"values\" must be an array of rows, one per wavelength"
                         : "\"values\" given per wavelength needs \"wavelengths_nm\"");
        goto done;
    }
    if (wl && ((st = json_get_numbers(&rd->json, wl, pw, 1, json_positive, &lambda, &m)) ||
               (st = json_check_ascending(&rd->json, pw, lambda, m))))
        goto done;
    if (per_wavelength && cJSON_GetArraySize(val) != m) {
        st = json_bad(&rd->json, path, "has %d wavelengths but %d rows of values", m, cJSON_GetArraySize(val));
        goto done;
    }
    mu = malloc(sizeof(double) * (size_t)n);
    rows = malloc(sizeof(double) * (size_t)n * (size_t)m);
    grid_values = malloc(sizeof(double) * (size_t)n * (size_t)rd->grid->count);
    if (!mu || !rows || !grid_values) {
        st = json_out_of_memory(&rd->json);
        goto done;
    }
    for (int j = 0; j < n; j++)
        mu[j] = cos(theta[j] * FM_DEG);
    mu[0] = 1.0;
    mu[n - 1] = -1.0;
    const cJSON *row = per_wavelength ? val->child : val;
    for (int i = 0; i < m; i++, row = row ? row->next : NULL) {
        char pr[JSON_PATH_CHARS];
        if (per_wavelength)
            json_child_path(pr, pv, "[%d]", i);
        else
            json_child_path(pr, pv, "%s", "");
        double *v = NULL;
        int nv = 0;
        if ((st = json_get_numbers(&rd->json, row, pr, 2, json_non_negative, &v, &nv)))
            goto done;
        if (nv != n) {
            free(v);
            st = json_bad(&rd->json, pr, "has %d values for %d angles", nv, n);
            goto done;
        }
        memcpy(rows + (size_t)i * n, v, sizeof(double) * (size_t)n);
        free(v);
        if (!normalise_row(mu, rows + (size_t)i * n, n)) {
            st = json_bad(&rd->json, pr, "integrates to 0 over the sphere");
            goto done;
        }
    }
    /* rows (each normalised) interpolated linearly in wavelength onto the grid */
    const spectral_grid *g = rd->grid;
    if (m > 1 && (g->lambda_nm[0] < lambda[0] || g->lambda_nm[g->count - 1] > lambda[m - 1])) {
        st = json_bad(&rd->json, pw, "given for %g-%g nm (constituent \"%s\"), but the render needs %g-%g nm",
                      lambda[0], lambda[m - 1], owner, g->lambda_nm[0], g->lambda_nm[g->count - 1]);
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
        st = json_bad(&rd->json, path, "%s", inner.message);
    else if (st)
        st = json_out_of_memory(&rd->json);
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
    if ((st = json_require_object(&rd->json, node, path)) || (st = json_check_keys(&rd->json, node, path, phase_keys)))
        return st;
    const cJSON *type = member(node, "type");
    char p[JSON_PATH_CHARS];
    json_child_path(p, path, ".type");
    if (!type)
        return json_bad(&rd->json, path, "missing \"type\" (\"rayleigh\", \"henyey-greenstein\" or \"tabulated\")");
    if (!cJSON_IsString(type))
        return json_bad(&rd->json, p, "must be a string, not %s", json_type_name(type));
    const int K = rd->grid->count;
    if (strcmp(type->valuestring, "rayleigh") == 0) {
        const char *const other[] = {"g", "angles_deg", "wavelengths_nm", "values", NULL};
        const json_interval rho_range = {0.0, MAX_RHO, 0, 0};
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
        /* closer to +-1 the phase function's peak (~ 1 / (2 pi (1 - |g|)^2) sr^-1) overflows its
         * sampling and the maps turn NaN (measured: fine at 0.999999, NaN at 0.99999999) */
        const json_interval g_range = {-0.99999, 0.99999, 0, 0};
        int present = 0;
        if ((st = refuse_keys(rd, node, path, "Henyey-Greenstein", other)) ||
            (st = optional_spectral(rd, node, path, "g", g_range, owner, 0.0, out->param, &present)))
            return st;
        if (!present)
            return json_bad(&rd->json, path, "missing \"g\" (the asymmetry parameter, in (-1, 1))");
        out->kind = PHASE_HENYEY_GREENSTEIN;
        return FM_OK;
    }
    if (strcmp(type->valuestring, "tabulated") == 0)
        return read_tabulated_phase(rd, node, path, owner, out);
    return json_bad(&rd->json, p,
                    "\"%s\" is not a phase function type (\"rayleigh\", \"henyey-greenstein\" or \"tabulated\")",
                    type->valuestring);
}

/* ---- constituents ----------------------------------------------------------------------------- */

static const char *const constituent_keys[] = {"name",       "profile", "scattering", "absorption", "extinction",
                                               "single_scattering_albedo", "phase", NULL};

static fm_status read_constituent(const reader *rd, const cJSON *node, const char *path, double top_m, species *sp,
                                  char *name, size_t name_size)
{
    fm_status st;
    if ((st = json_require_object(&rd->json, node, path)) ||
        (st = json_check_keys(&rd->json, node, path, constituent_keys)))
        return st;
    const char *nm;
    if ((st = json_get_string(&rd->json, node, path, "name", 0, &nm)))
        return st;
    if (nm)
        snprintf(name, name_size, "%s", nm);
    sp->name = name;

    /* coefficients: scattering + absorption, or extinction + single-scattering albedo */
    const int K = rd->grid->count;
    const json_interval coefficient = {0.0, MAX_COEFFICIENT, 0, 0};
    int has_ext = member(node, "extinction") != NULL, has_ssa = member(node, "single_scattering_albedo") != NULL;
    if (has_ext || has_ssa) {
        if (member(node, "scattering") || member(node, "absorption"))
            return json_bad(&rd->json, path,
                            "give either \"scattering\" and \"absorption\" or \"extinction\" and "
                            "\"single_scattering_albedo\", not both");
        if (!has_ext || !has_ssa)
            return json_bad(&rd->json, path, "\"%s\" needs \"%s\"", has_ext ? "extinction" : "single_scattering_albedo",
                            has_ext ? "single_scattering_albedo" : "extinction");
        double ext[FM_MAX_WAVELENGTHS], ssa[FM_MAX_WAVELENGTHS];
        const json_interval unit = {0.0, 1.0, 0, 0};
        if ((st = optional_spectral(rd, node, path, "extinction", coefficient, name, 0.0, ext, NULL)) ||
            (st = optional_spectral(rd, node, path, "single_scattering_albedo", unit, name, 0.0, ssa, NULL)))
            return st;
        for (int k = 0; k < K; k++) {
            sp->sigma_s[k] = ext[k] * ssa[k];
            sp->sigma_a[k] = ext[k] - sp->sigma_s[k];
        }
    } else {
        int has_s = 0, has_a = 0;
        if ((st = optional_spectral(rd, node, path, "scattering", coefficient, name, 0.0, sp->sigma_s, &has_s)) ||
            (st = optional_spectral(rd, node, path, "absorption", coefficient, name, 0.0, sp->sigma_a, &has_a)))
            return st;
        if (!has_s && !has_a)
            return json_bad(&rd->json, path,
                            "missing coefficients: \"scattering\" and/or \"absorption\", or \"extinction\" and "
                            "\"single_scattering_albedo\" (m^-1)");
    }

    const cJSON *phase = member(node, "phase");
    if (phase) {
        char p[JSON_PATH_CHARS];
        json_child_path(p, path, ".phase");
        if ((st = read_phase(rd, phase, p, name, &sp->phase)))
            return st;
    } else {
        for (int k = 0; k < K; k++)
            if (sp->sigma_s[k] > 0.0)
                return json_bad(&rd->json, path, "missing \"phase\": the constituent scatters");
        sp->phase.kind = PHASE_NONE;
    }

    const cJSON *profile = member(node, "profile");
    if (!profile)
        return json_bad(&rd->json, path, "missing \"profile\"");
    char p[JSON_PATH_CHARS];
    json_child_path(p, path, ".profile");
    return read_profile(rd, profile, p, top_m, &sp->profile);
}

/* ---- the file --------------------------------------------------------------------------------- */

static double file_solar(const void *ctx, double lambda_nm)
{
    const spectral *s = ctx;
    return s->count == 1 ? s->value[0] : interpolate_clamped(s->lambda_nm, s->value, s->count, lambda_nm);
}

/* "clouds" (cloud layers over the constituents) is read by aerosol/cloud_file.c, a layer above this one */
static const char *const top_keys[] = {"name",          "description",      "planet_radius_km", "top_altitude_km",
                                       "ground_albedo", "solar_irradiance", "constituents",     "clouds",
                                       NULL};

static fm_status build(const reader *rd, const cJSON *root, atmosphere *atm, double solar_scale, double ground_albedo)
{
    fm_status st;
    if ((st = json_require_object(&rd->json, root, "$")) || (st = json_check_keys(&rd->json, root, "$", top_keys)))
        return st;
    const char *name, *description;
    if ((st = json_get_string(&rd->json, root, "$", "name", 0, &name)) ||
        (st = json_get_string(&rd->json, root, "$", "description", 0, &description)))
        return st;
    const json_interval radius = {MIN_RADIUS_KM, MAX_RADIUS_KM, 0, 0}, top = {MIN_TOP_KM, MAX_TOP_KM, 0, 0}, unit = {0.0, 1.0, 0, 0};
    double radius_km, top_km;
    if ((st = json_required_number(&rd->json, root, "$", "planet_radius_km", radius, &radius_km)) ||
        (st = json_required_number(&rd->json, root, "$", "top_altitude_km", top, &top_km)))
        return st;
    atm->bottom_radius_m = radius_km * FM_KM;
    atm->top_radius_m = (radius_km + top_km) * FM_KM;
    double top_m = top_km * FM_KM;

    if ((st = optional_spectral(rd, root, "$", "ground_albedo", unit, NULL, ground_albedo, atm->ground_albedo, NULL)))
        return st;

    const cJSON *solar = member(root, "solar_irradiance");
    if (solar) {
        spectral s;
        /* the sun's own ~2 W m^-2 nm^-1 times a million: a larger value overflows the disk's radiance
         * (E / its 6.8e-5 sr) in the EXR's 32-bit floats */
        const json_interval solar_range = {0.0, 1e6, 0, 0};
        if ((st = read_spectral(rd, solar, "$.solar_irradiance", solar_range, &s)))
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

    const cJSON *list;
    if ((st = json_get_array(&rd->json, root, "$", "constituents", 1, FM_MAX_SPECIES, "constituents", &list)))
        return st;
    int count = cJSON_GetArraySize(list);
    int i = 0;
    for (const cJSON *it = list->child; it; it = it->next, i++) {
        char p[JSON_PATH_CHARS];
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
    reader rd = {{path, "atmosphere_file", err}, &atm->grid};
    fm_status st;
    cJSON *root = json_reader_load(&rd.json, &st);
    if (!root)
        return st;
    st = build(&rd, root, atm, solar_scale, ground_albedo);
    cJSON_Delete(root);
    if (st) {
        atmosphere_free(atm);
        return st;
    }
    atmosphere_update_majorants(atm);
    return FM_OK;
}

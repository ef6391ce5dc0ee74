#include "aerosol/cloud_layer.h"

#include "aerosol/cloud_optics.h"
#include "base/status.h"
#include "base/units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the layer as a species ------------------------------------------------------------------ */

typedef struct slab {
    double base_m, top_m;
} slab;

/* 1 inside the layer; the nodes on an edge above the ground hold half, so the piecewise-linear
 * column is the slab's (as aerosol.c's layers). */
static double slab_shape(void *ctx, double z)
{
    const slab *l = ctx;
    const double eps = 1e-6;
    if (z < l->base_m - eps || z > l->top_m + eps)
        return 0.0;
    return (l->base_m > 0.0 && fabs(z - l->base_m) <= eps) || fabs(z - l->top_m) <= eps ? 0.5 : 1.0;
}

/* Delta-M (Wiscombe 1977, J. Atmos. Sci. 34, 1408) for the fast path's multiple scattering under
 * decks the sun does not pierce (sky.h): the phase function's forward peak within PEAK_ANGLE_DEG is
 * cut to its value there, and the light it held, a fraction f of the scattering, goes on as if not
 * scattered (sigma_s times 1 - f; the table renormalises what is left).  The droplets' diffraction
 * peak (a 0.4-0.7 degree half-width) lies inside; scattered by at most this angle, the diffuse light
 * under a deck moves by less than its own angular detail, and the similarity parameter (1 - g) tau
 * that sets a thick layer's transmission changes by f (1 - <cos>_peak) tau, about 1e-4 of it
 * (docs/decisions/2026-12-06-thick-media-speed.md). */
#define PEAK_ANGLE_DEG 3.0

/* Cuts the forward peak of one wavelength's values at the angles theta (ascending, n of them) and
 * returns the fraction f of the scattering it held, measured as phase_table.h normalises (trapezoids
 * in cos theta). */
double cloud_truncate_peak(double *values, const double *theta, int n)
{
    int jc = 0;
    while (jc < n - 1 && theta[jc] < PEAK_ANGLE_DEG * FM_DEG)
        jc++;
    double total = 0.0, cut = 0.0;
    for (int j = 0; j + 1 < n; j++) {
        double dmu = cos(theta[j]) - cos(theta[j + 1]);
        total += 0.5 * (values[j] + values[j + 1]) * dmu;
        if (j < jc)
            cut += 0.5 * (values[j] + values[j + 1] - 2.0 * values[jc]) * dmu;
    }
    for (int j = 0; j < jc; j++)
        values[j] = values[jc];
    return total > 0.0 && cut > 0.0 ? cut / total : 0.0;
}

/* Extinction relative to 550 nm, single-scattering albedo and phase table at every grid wavelength. */
static fm_status water_species(species *sp, const cloud_type *t, const spectral_grid *grid, int threads,
                               const char *cache_dir, double *ext_rel, double *ssa, double *peak, fm_error *err)
{
    cloud_water_table tb;
    fm_status s = cloud_water_table_get(t, grid, threads, cache_dir, &tb, NULL, err);
    if (s)
        return s;
    memcpy(ext_rel, tb.ext_rel, sizeof(double) * (size_t)grid->count);
    memcpy(ssa, tb.ssa, sizeof(double) * (size_t)grid->count);
    double theta[CLOUD_ANGLE_COUNT];
    for (int j = 0; j < CLOUD_ANGLE_COUNT; j++)
        theta[j] = cloud_angle_rad(j);
    for (int k = 0; peak && k < grid->count; k++)
        peak[k] = cloud_truncate_peak(tb.phase + (size_t)k * CLOUD_ANGLE_COUNT, theta, CLOUD_ANGLE_COUNT);
    s = phase_init_tabulated(&sp->phase, grid->count, CLOUD_ANGLE_COUNT, theta, tb.phase, err);
    cloud_water_table_free(&tb);
    return s;
}

static fm_status ice_species(species *sp, int K, double *ext_rel, double *ssa, double *peak, fm_error *err)
{
    double theta[CLOUD_ANGLE_COUNT], *values = malloc(sizeof(double) * (size_t)K * CLOUD_ANGLE_COUNT);
    if (!values)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the cloud phase functions");
    for (int j = 0; j < CLOUD_ANGLE_COUNT; j++) {
        theta[j] = cloud_angle_rad(j);
        double p = cloud_ice_phase(cos(theta[j]));
        for (int k = 0; k < K; k++)
            values[(size_t)k * CLOUD_ANGLE_COUNT + j] = p;
    }
    for (int k = 0; k < K; k++) {
        ext_rel[k] = ssa[k] = 1.0;
        if (peak)
            peak[k] = cloud_truncate_peak(values + (size_t)k * CLOUD_ANGLE_COUNT, theta, CLOUD_ANGLE_COUNT);
    }
    fm_status s = phase_init_tabulated(&sp->phase, K, CLOUD_ANGLE_COUNT, theta, values, err);
    free(values);
    return s;
}

fm_status cloud_add_layer(atmosphere *atm, const cloud_type *t, double base_m, double thickness_m, double tau550,
                          int threads, const char *cache_dir, int truncate_peak, fm_error *err)
{
    const int K = atm->grid.count;
    double top_m = atm->top_radius_m - atm->bottom_radius_m;
    if (!(base_m >= 0.0 && thickness_m > 0.0 && base_m + thickness_m < top_m))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cloud layer %g-%g m is not inside the atmosphere (0-%g m)", base_m,
                       base_m + thickness_m, top_m);
    species *sp = atmosphere_new_species(atm, 1);
    if (!sp)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "too many constituents (at most %d)", FM_MAX_SPECIES);
    sp->name = t->name;
    double ext_rel[FM_MAX_WAVELENGTHS], ssa[FM_MAX_WAVELENGTHS], peak[FM_MAX_WAVELENGTHS] = {0};
    double *cut = truncate_peak ? peak : NULL;
    fm_status s = t->ice ? ice_species(sp, K, ext_rel, ssa, cut, err)
                         : water_species(sp, t, &atm->grid, threads, cache_dir, ext_rel, ssa, cut, err);
    slab l = {base_m, base_m + thickness_m};
    if (!s && profile_sample(&sp->profile, slab_shape, &l, top_m, FM_PROFILE_SPACING_M))
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the cloud profile");
    if (s)
        return s;
    /* the extinction at 550 nm that gives exactly tau550 over the sampled profile's column */
    double column_m = profile_column(&sp->profile);
    if (!(column_m > 0.0))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cloud layer %g-%g m is thinner than the %g m profile grid",
                       base_m, base_m + thickness_m, FM_PROFILE_SPACING_M);
    double beta550 = tau550 / column_m;
    for (int k = 0; k < K; k++) {
        sp->sigma_s[k] = beta550 * ext_rel[k] * ssa[k] * (1.0 - peak[k]);
        sp->sigma_a[k] = beta550 * ext_rel[k] * (1.0 - ssa[k]);
    }
    return FM_OK;
}

double cloud_shell_chord_m(double r, double mu, double r_base, double r_top)
{
    /* distance along the ray to radius R (>= r) going outward: sqrt(R^2 - r^2 (1 - mu^2)) - r mu */
    double b2 = r * r * (1.0 - mu * mu);
    double to_top = r < r_top ? sqrt(r_top * r_top - b2) - r * mu : 0.0;
    double to_base = r < r_base ? sqrt(r_base * r_base - b2) - r * mu : 0.0;
    return fmax(to_top - to_base, 0.0);
}

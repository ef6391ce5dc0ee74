#include "aerosol/cloud.h"

#include "base/status.h"
#include "base/threads.h"
#include "base/units.h"
#include "data/tables.h"
#include "phase/phase_hg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Droplet spectra: the headers of OPAC's optdat files (Hess, Koepke & Schult 1998), dN/dr = A r^alpha
 * exp(-B r^gamma) over 0.02-50 um; effective radii 7.33 um (stco), 11.3 um (stma), 10.7 um (fogr).
 * The genera without an OPAC spectrum of their own take the nearest one: altostratus the continental
 * stratus, nimbostratus the maritime.  The default layers are presets/clouds/TYPE.json. */
#define STCO {5.0, 0.938, 1.05, 0.02, 50.0}
#define STMA {3.0, 0.193, 1.3, 0.02, 50.0}
#define FOGR {4.0, 0.0562, 1.77, 0.02, 50.0}
#define NO_SIZE {0.0, 0.0, 0.0, 0.0, 0.0}

const cloud_type cloud_types[] = {
    {"stratus", 0, STCO, "OPAC stratus (continental)"},
    {"stratocumulus", 0, STMA, "OPAC stratus (maritime)"},
    {"altostratus", 0, STCO, "OPAC stratus (continental)"},
    {"nimbostratus", 0, STMA, "OPAC stratus (maritime)"},
    {"fog", 0, FOGR, "OPAC fog"},
    {"cirrostratus", 1, NO_SIZE, "two-term Henyey-Greenstein, g = 0.77"},
    {"cirrus", 1, NO_SIZE, "two-term Henyey-Greenstein, g = 0.77"},
    {NULL, 0, NO_SIZE, NULL},
};

const cloud_type *cloud_type_find(const char *name)
{
    for (const cloud_type *t = cloud_types; name && t->name; t++)
        if (strcmp(t->name, name) == 0)
            return t;
    return NULL;
}

void cloud_type_names(char *out, size_t size)
{
    size_t used = 0;
    if (size)
        out[0] = '\0';
    for (const cloud_type *t = cloud_types; t->name && used < size; t++) {
        int n = snprintf(out + used, size - used, "%s%s", t == cloud_types ? "" : ", ", t->name);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

double cloud_angle_rad(int j)
{
    double t = (double)j / (CLOUD_ANGLE_COUNT - 1);
    return FM_PI * t * t;
}

/* Ice: p = f HG(g1) + (1 - f) HG(-g2).  The forward lobe carries the diffraction and the refracted
 * light, the backward one the internal reflections of hexagonal crystals; the total asymmetry
 * f g1 - (1 - f) g2 = 0.77 lies in the 0.74-0.80 of ray-traced habit mixtures and in-situ cirrus
 * (Baum et al. 2005, J. Appl. Meteor. 44, 1896; Garrett et al. 2003, GRL 30, 2132). */
#define ICE_F 0.96
#define ICE_G1 0.823
#define ICE_G2 0.50

double cloud_ice_phase(double cos_theta)
{
    return ICE_F * phase_hg_eval(cos_theta, ICE_G1) + (1.0 - ICE_F) * phase_hg_eval(cos_theta, -ICE_G2);
}

double cloud_ice_asymmetry(void)
{
    return ICE_F * ICE_G1 - (1.0 - ICE_F) * ICE_G2;
}

/* m = n - ik of liquid water at lambda_nm, linear between the table's rows. */
static double complex water_index(double lambda_nm)
{
    double um = lambda_nm * 1e-3;
    int i = 0;
    while (i + 2 < FM_WATER_INDEX_COUNT && fm_water_index[i + 1][0] < um)
        i++;
    double t = (um - fm_water_index[i][0]) / (fm_water_index[i + 1][0] - fm_water_index[i][0]);
    double n = fm_water_index[i][1] + t * (fm_water_index[i + 1][1] - fm_water_index[i][1]);
    double k = fm_water_index[i][2] + t * (fm_water_index[i + 1][2] - fm_water_index[i][2]);
    return n - k * I;
}

fm_status cloud_water_optics(const cloud_type *t, double lambda_nm, mie_lognormal_result *out, double *phase,
                             fm_error *err)
{
    double mu[CLOUD_ANGLE_COUNT] = {0};
    int n_mu = phase ? CLOUD_ANGLE_COUNT : 0;
    for (int j = 0; j < n_mu; j++)
        mu[j] = cos(cloud_angle_rad(j));
    if (!(lambda_nm >= 250.0 && lambda_nm <= 1250.0))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cloud optics cover 250-1250 nm, not %g nm", lambda_nm);
    if (t->ice || mie_modified_gamma(&t->size, lambda_nm * 1e-3, water_index(lambda_nm), NULL, n_mu, mu, phase, out))
        return fm_fail(err, FM_ERR_INTERNAL, "Mie integration failed for cloud type '%s'", t->name);
    return FM_OK;
}

fm_status cloud_tau_from_lwp(const cloud_type *t, double lwp_gm2, double *tau550, fm_error *err)
{
    if (t->ice)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "'%s' is an ice cloud: give its optical depth, not a liquid water path",
                       t->name);
    mie_lognormal_result r;
    fm_status s = cloud_water_optics(t, 550.0, &r, NULL, err);
    if (s)
        return s;
    double volume_m3 = modified_gamma_mean_volume_um3(&t->size) * 1e-18;
    *tau550 = lwp_gm2 * 1e-3 * r.ext_m2 / (CLOUD_WATER_DENSITY * volume_m3);
    return FM_OK;
}

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

typedef struct water_job {
    const cloud_type *type;
    const spectral_grid *grid;
    mie_lognormal_result *result; /* [K] */
    double *phase;                /* [K][CLOUD_ANGLE_COUNT] */
    int failed;
} water_job;

static void water_items(void *ctx, int64_t begin, int64_t end, int thread)
{
    (void)thread;
    water_job *jb = ctx;
    for (int64_t k = begin; k < end; k++)
        if (cloud_water_optics(jb->type, jb->grid->lambda_nm[k], &jb->result[k],
                               jb->phase + (size_t)k * CLOUD_ANGLE_COUNT, NULL))
            jb->failed = 1;
}

/* Extinction relative to 550 nm, single-scattering albedo and phase table at every grid wavelength. */
static fm_status water_species(species *sp, const cloud_type *t, const spectral_grid *grid, int threads,
                               double *ext_rel, double *ssa, fm_error *err)
{
    const int K = grid->count;
    mie_lognormal_result r550, result[FM_MAX_WAVELENGTHS];
    fm_status s = cloud_water_optics(t, 550.0, &r550, NULL, err);
    if (s)
        return s;
    double *phase = malloc(sizeof(double) * (size_t)K * CLOUD_ANGLE_COUNT);
    if (!phase)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the cloud phase functions");
    water_job jb = {t, grid, result, phase, 0};
    s = parallel_for(threads, K, 1, water_items, &jb, NULL, NULL);
    if (!s && jb.failed)
        s = fm_fail(err, FM_ERR_INTERNAL, "Mie integration failed for cloud type '%s'", t->name);
    if (!s) {
        for (int k = 0; k < K; k++) {
            ext_rel[k] = result[k].ext_m2 / r550.ext_m2;
            ssa[k] = result[k].sca_m2 / result[k].ext_m2;
        }
        double theta[CLOUD_ANGLE_COUNT];
        for (int j = 0; j < CLOUD_ANGLE_COUNT; j++)
            theta[j] = cloud_angle_rad(j);
        s = phase_init_tabulated(&sp->phase, K, CLOUD_ANGLE_COUNT, theta, phase, err);
    }
    free(phase);
    return s;
}

static fm_status ice_species(species *sp, int K, double *ext_rel, double *ssa, fm_error *err)
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
    for (int k = 0; k < K; k++)
        ext_rel[k] = ssa[k] = 1.0;
    fm_status s = phase_init_tabulated(&sp->phase, K, CLOUD_ANGLE_COUNT, theta, values, err);
    free(values);
    return s;
}

fm_status cloud_add_layer(atmosphere *atm, const cloud_type *t, double base_m, double thickness_m, double tau550,
                          int threads, fm_error *err)
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
    double ext_rel[FM_MAX_WAVELENGTHS], ssa[FM_MAX_WAVELENGTHS];
    fm_status s = t->ice ? ice_species(sp, K, ext_rel, ssa, err)
                         : water_species(sp, t, &atm->grid, threads, ext_rel, ssa, err);
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
        sp->sigma_s[k] = beta550 * ext_rel[k] * ssa[k];
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

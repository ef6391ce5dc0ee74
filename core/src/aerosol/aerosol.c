#include "aerosol/aerosol.h"

#include "base/status.h"
#include "base/units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const int humidities[] = {0, 50, 70, 80, 90, 95, 98, 99};
#define HUMIDITY_COUNT ((int)(sizeof humidities / sizeof humidities[0]))

/* Adds w times the table's values at wavelength node i into out. */
static void accumulate(const aerosol_optics *t, int i, double w, int with_phase, component_optics *out)
{
    out->ext_m2 += w * t->ext_m2[i];
    out->sca_m2 += w * t->sca_m2[i];
    /* g and the phase function are per scattered photon: weight them by scattering */
    double ws = w * t->sca_m2[i];
    out->g += ws * t->g[i];
    if (with_phase)
        for (int j = 0; j < AEROSOL_ANGLE_COUNT; j++)
            out->phase[j] += ws * t->phase[i][j];
}

fm_status component_optics_at(const char *code, double humidity_percent, double lambda_nm, int with_phase,
                              component_optics *out, fm_error *err)
{
    memset(out, 0, sizeof *out);
    double f = (lambda_nm - AEROSOL_FIRST_NM) / AEROSOL_STEP_NM;
    if (!(f >= -1e-9 && f <= AEROSOL_WAVELENGTH_COUNT - 1 + 1e-9))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "aerosol tables cover %g-%g nm, not %g nm", AEROSOL_FIRST_NM,
                       AEROSOL_FIRST_NM + AEROSOL_STEP_NM * (AEROSOL_WAVELENGTH_COUNT - 1), lambda_nm);
    int i = (int)fmin(fmax(floor(f), 0.0), AEROSOL_WAVELENGTH_COUNT - 2);
    double tl = fmin(fmax(f - i, 0.0), 1.0);

    /* bracketing humidities; a component without hygroscopic growth has only the dry table */
    const aerosol_optics *lo = NULL, *hi = NULL;
    double th = 0.0;
    if (!aerosol_optics_find(code, 50)) {
        lo = hi = aerosol_optics_find(code, 0);
    } else {
        int h = 0;
        while (h < HUMIDITY_COUNT - 2 && humidity_percent > humidities[h + 1])
            h++;
        lo = aerosol_optics_find(code, humidities[h]);
        hi = aerosol_optics_find(code, humidities[h + 1]);
        th = fmin(fmax((humidity_percent - humidities[h]) / (humidities[h + 1] - humidities[h]), 0.0), 1.0);
    }
    if (!lo || !hi)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "no optical table for aerosol component '%s'", code);
    accumulate(lo, i, (1 - th) * (1 - tl), with_phase, out);
    accumulate(lo, i + 1, (1 - th) * tl, with_phase, out);
    accumulate(hi, i, th * (1 - tl), with_phase, out);
    accumulate(hi, i + 1, th * tl, with_phase, out);
    if (out->sca_m2 > 0.0) {
        out->g /= out->sca_m2;
        if (with_phase)
            for (int j = 0; j < AEROSOL_ANGLE_COUNT; j++)
                out->phase[j] /= out->sca_m2;
    }
    return FM_OK;
}

/* ---- a layer's vertical shape ---------------------------------------------------------------- */

/* Relative density (1 at the layer's bottom).  The nodes exactly on a layer boundary hold half the
 * value, so the piecewise-linear profile's column equals the layer's exact column (to O(dz^2))
 * even though each boundary is a step smeared over one grid cell. */
static double layer_shape(void *ctx, double z)
{
    const biome_layer *l = ctx;
    const double eps = 1e-6;
    if (z < l->bottom_m - eps || z > l->top_m + eps)
        return 0.0;
    double v = l->scale_height_m > 0.0 ? exp(-(z - l->bottom_m) / l->scale_height_m) : 1.0;
    if ((l->bottom_m > 0.0 && fabs(z - l->bottom_m) <= eps) || fabs(z - l->top_m) <= eps)
        v *= 0.5;
    return v;
}

/* Column of the shape (m), exact for the layer: integral of exp(-(z - bottom)/H) over the layer. */
static double layer_column_m(const biome_layer *l)
{
    double d = l->top_m - l->bottom_m;
    return l->scale_height_m > 0.0 ? l->scale_height_m * -expm1(-d / l->scale_height_m) : d;
}

static double layer_humidity(const biome_layer *l, double ambient)
{
    return l->humidity_percent >= 0.0 ? l->humidity_percent : ambient;
}

/* The layer's mixture at one wavelength: extinction and scattering coefficients (m^-1 at the
 * bottom, turbidity 1), g, and optionally the phase function. */
static fm_status layer_mixture(const biome_layer *l, double humidity, double lambda_nm, double *ext, double *sca,
                               double *g, double *phase, fm_error *err)
{
    *ext = *sca = *g = 0.0;
    if (phase)
        memset(phase, 0, sizeof(double) * AEROSOL_ANGLE_COUNT);
    component_optics c;
    for (int i = 0; i < l->component_count; i++) {
        fm_status s = component_optics_at(l->component[i].code, humidity, lambda_nm, phase != NULL, &c, err);
        if (s)
            return s;
        double n = l->component[i].density_m3;
        *ext += n * c.ext_m2;
        *sca += n * c.sca_m2;
        *g += n * c.sca_m2 * c.g;
        if (phase)
            for (int j = 0; j < AEROSOL_ANGLE_COUNT; j++)
                phase[j] += n * c.sca_m2 * c.phase[j];
    }
    if (*sca > 0.0) {
        *g /= *sca;
        if (phase)
            for (int j = 0; j < AEROSOL_ANGLE_COUNT; j++)
                phase[j] /= *sca;
    }
    return FM_OK;
}

static fm_status add_layer(atmosphere *atm, const biome_layer *l, double humidity, double turbidity,
                           fm_aerosol_phase model, fm_error *err)
{
    const int K = atm->grid.count;
    double ext[FM_MAX_WAVELENGTHS], sca[FM_MAX_WAVELENGTHS], g[FM_MAX_WAVELENGTHS];
    double *phase = malloc(sizeof(double) * (size_t)K * AEROSOL_ANGLE_COUNT);
    double theta[AEROSOL_ANGLE_COUNT];
    if (!phase)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the aerosol phase functions");
    fm_status s = FM_OK;
    double any = 0.0;
    for (int k = 0; k < K && !s; k++) {
        s = layer_mixture(l, humidity, atm->grid.lambda_nm[k], &ext[k], &sca[k], &g[k],
                          phase + (size_t)k * AEROSOL_ANGLE_COUNT, err);
        any += sca[k];
    }
    if (s || !(any * turbidity > 0.0)) {
        free(phase);
        return s;
    }
    species *sp = atmosphere_new_species(atm, 1);
    if (!sp) {
        free(phase);
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "too many constituents (at most %d)", FM_MAX_SPECIES);
    }
    sp->name = "aerosol";
    /* the profile is the relative density; the cross sections are the layer's coefficients */
    for (int k = 0; k < K; k++) {
        sp->sigma_s[k] = turbidity * sca[k];
        sp->sigma_a[k] = turbidity * fmax(ext[k] - sca[k], 0.0);
    }
    if (model == FM_AEROSOL_PHASE_HG) {
        sp->phase.kind = PHASE_HENYEY_GREENSTEIN;
        for (int k = 0; k < K; k++)
            sp->phase.param[k] = g[k];
    } else {
        for (int j = 0; j < AEROSOL_ANGLE_COUNT; j++)
            theta[j] = aerosol_optics_angle_rad(j);
        s = phase_init_tabulated(&sp->phase, K, AEROSOL_ANGLE_COUNT, theta, phase, err);
    }
    free(phase);
    if (!s && profile_sample(&sp->profile, layer_shape, (void *)l, atm->top_radius_m - atm->bottom_radius_m,
                             FM_PROFILE_SPACING_M))
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the aerosol profile");
    return s;
}

fm_status aerosol_add_biome(atmosphere *atm, const biome *b, double humidity_percent, double turbidity,
                            fm_aerosol_phase model, fm_error *err)
{
    for (int i = 0; i < b->layer_count; i++) {
        fm_status s = add_layer(atm, &b->layer[i], layer_humidity(&b->layer[i], humidity_percent), turbidity,
                                model, err);
        if (s)
            return s;
    }
    return FM_OK;
}

fm_status aerosol_biome_column(const biome *b, double humidity_percent, double lambda_nm, aerosol_column *out,
                               fm_error *err)
{
    memset(out, 0, sizeof *out);
    double gs = 0.0;
    for (int i = 0; i < b->layer_count; i++) {
        const biome_layer *l = &b->layer[i];
        double ext, sca, g;
        fm_status s = layer_mixture(l, layer_humidity(l, humidity_percent), lambda_nm, &ext, &sca, &g, NULL, err);
        if (s)
            return s;
        double column = layer_column_m(l);
        if (l->bottom_m <= 0.0)
            out->ext_ground_per_m += ext;
        out->tau_ext += ext * column;
        out->tau_sca += sca * column;
        gs += g * sca * column;
    }
    out->g = out->tau_sca > 0.0 ? gs / out->tau_sca : 0.0;
    return FM_OK;
}

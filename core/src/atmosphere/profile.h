/* Number density of one constituent versus altitude, tabulated on a uniform grid and linearly
 * interpolated.  This piecewise-linear function *is* the medium that every estimator sees: free
 * flights, transmittance tables and quadratures are all exact (or converged) for it.  At 50 m spacing
 * it differs from an exponential of 8 km scale height by under 3e-6 (1e-4 for 1 km). */
#ifndef FM_ATMOSPHERE_PROFILE_H
#define FM_ATMOSPHERE_PROFILE_H

#include "firmament/firmament.h"

#define FM_PROFILE_SPACING_M 50.0

typedef struct density_profile {
    double dz_m;  /* grid spacing */
    int count;    /* nodes at altitude i * dz_m, i in [0, count) */
    double *n;    /* m^-3 */
} density_profile;

typedef double (*density_fn)(void *ctx, double altitude_m);

/* Samples fn on [0, top_m]; returns FM_ERR_OUT_OF_MEMORY on allocation failure. */
fm_status profile_sample(density_profile *p, density_fn fn, void *ctx, double top_m, double dz_m);
void profile_free(density_profile *p);

/* Density at f = altitude / dz_m (grid steps) for f > 0, with i = (int)f and t = f - i (taken once
 * for several profiles on one grid): linear between nodes, 0 above the top node. */
static inline double profile_density_between(const density_profile *p, double f, int i, double t)
{
    if (i >= p->count - 1)
        return i == p->count - 1 && f == (double)i ? p->n[i] : 0.0;
    return p->n[i] + (p->n[i + 1] - p->n[i]) * t;
}

/* Density at f = altitude / dz_m (grid steps): linear between nodes, constant below 0, 0 above the
 * top node. */
static inline double profile_density_at(const density_profile *p, double f)
{
    if (f <= 0.0)
        return p->n[0];
    int i = (int)f;
    return profile_density_between(p, f, i, f - i);
}

/* Density at altitude (m). */
static inline double profile_density(const density_profile *p, double altitude_m)
{
    return profile_density_at(p, altitude_m / p->dz_m);
}

/* Column (m^-2 for densities in m^-3): the integral of the piecewise-linear profile from the ground
 * to its top node. */
double profile_column(const density_profile *p);

/* Maximum density over [z0, z1] (exact for the piecewise-linear function). */
double profile_max(const density_profile *p, double z0_m, double z1_m);

#endif

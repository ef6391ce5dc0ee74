/* Diffuse (sky) irradiance on the ground, for the fast path.
 *
 * Light reflected by a Lambertian ground toward the observer is albedo / pi times the ground's
 * total irradiance, direct plus diffuse.  By spherical symmetry the diffuse part at a ground point
 * depends only on the local sun zenith angle, so it is computed once per render on a few angles
 * spanning the ground the observer can see (one for an observer on the ground, two at eye height,
 * up to five from high up, at most 0.5 degrees apart):
 *  - order 1 (sunlight scattered once on its way down) by deterministic quadrature of the
 *    single-scattering radiance over the ground point's sky (single_scatter.h), on a grid crowded
 *    at the horizon and about the sun, where an aerosol's forward peak is;
 *  - orders >= 2 (ground-sky interreflections included) by many paths: pi * mean(L) over
 *    cosine-distributed directions; or, for an observer on the ground, by the caller from the
 *    multiple-scattering table, whose sky half is that very radiance (render.c, ground_from_table).
 * Order 1 is most of the diffuse light by day and, through the aerosols' forward peak, most of the
 * paths' noise, so it is integrated rather than sampled.  The fast path then adds the ground's
 * reflection deterministically and its multiple-scattering paths skip the ground as a first interaction, so
 * nothing is counted twice and the ground carries no per-direction noise. */
#ifndef FM_TRANSPORT_GROUND_IRRADIANCE_H
#define FM_TRANSPORT_GROUND_IRRADIANCE_H

#include "firmament/firmament.h"

typedef struct ground_irradiance {
    int count;                /* angles */
    double theta0, dtheta;    /* node i at local sun zenith angle theta0 + i dtheta (rad) */
    double *E;                /* [count][K]: W m^-2 nm^-1 */
    int K;
} ground_irradiance;

void ground_irradiance_free(ground_irradiance *g);

/* How many sun angles the table for (theta_s, max_offset) has: 1 when the observer is on the
 * ground and sees only the ground at its feet. */
int ground_irradiance_angle_count(double theta_s, double max_offset);

/* Adds E[k] (W m^-2 nm^-1, every grid wavelength) to every angle's irradiance. */
void ground_irradiance_add(ground_irradiance *g, const double *E);

/* Diffuse irradiance for every grid wavelength at a ground point whose local sun zenith cosine is mu_s. */
void ground_irradiance_lookup(const ground_irradiance *g, double mu_s, double *E);

#endif

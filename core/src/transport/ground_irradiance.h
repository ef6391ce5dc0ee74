/* Diffuse (sky) irradiance on the ground, for the fast path.
 *
 * Light reflected by a Lambertian ground toward the observer is albedo / pi times the ground's
 * total irradiance, direct plus diffuse.  By spherical symmetry the diffuse part at a ground point
 * depends only on the local sun zenith angle, so it is estimated once per render on a few angles
 * spanning the ground the observer can see (one angle for an observer on the ground), with many
 * paths each: E_d = pi * mean(L) over cosine-distributed directions, all orders of scattering
 * (ground-sky interreflections included).  The fast path then adds the ground's reflection
 * deterministically and its multiple-scattering paths skip the ground as a first interaction, so
 * nothing is counted twice and the ground carries no per-direction noise. */
#ifndef FM_TRANSPORT_GROUND_IRRADIANCE_H
#define FM_TRANSPORT_GROUND_IRRADIANCE_H

#include "firmament/firmament.h"
#include "transport/path.h"

typedef struct ground_irradiance {
    int count;                /* angles */
    double theta0, dtheta;    /* node i at local sun zenith angle theta0 + i dtheta (rad) */
    double *E;                /* [count][K]: W m^-2 nm^-1 */
    int K;
} ground_irradiance;

/* Builds the table for local sun zenith angles within max_offset (rad) of theta_s. */
fm_status ground_irradiance_build(ground_irradiance *g, const path_context *all_orders, double theta_s,
                                  double max_offset, int paths, uint64_t seed, int threads, const atomic_int *cancel);
void ground_irradiance_free(ground_irradiance *g);

/* Diffuse irradiance for every grid wavelength at a ground point whose local sun zenith cosine is mu_s. */
void ground_irradiance_lookup(const ground_irradiance *g, double mu_s, double *E);

#endif

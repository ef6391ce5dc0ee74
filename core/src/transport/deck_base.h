/* The light coming down from the base of a deck that the sun does not pierce (sky.h,
 * SKY_TRUNCATE_TAU), by light tracing, for the fast path's paths that stay below the deck.
 *
 * The atmosphere is horizontally uniform, so every photon the sun sends into it that comes down
 * through the deck's base counts: photons leave the top of the atmosphere along the sun's direction
 * and random-walk through a plane-parallel copy of its column (layers with the column's mean
 * coefficients, the Lambertian ground included), one grid wavelength each; every downward crossing
 * of the base altitude by a photon that has scattered adds its weight to the projection of the
 * base's diffuse radiance on a smooth basis,
 *     L(mu, phi) = sum_j sum_m a_jm B_j(mu) cos(m phi),
 * B_j polynomials in sqrt(mu) orthonormal for the weight mu on [0, 1] (mu the view's zenith
 * cosine), phi the view's azimuth from the sun's (under a deck the light has forgotten the sun's
 * azimuth: m = 0 alone).  A photon of energy E0 mu0 / N per unit area crossing along the
 * view (mu, phi) estimates L mu dOmega, so a_jm is the mean of B_j(mu) cos(m phi) (E0 mu0 / N) / norm_m
 * (norm_0 = 2 pi, else pi): no 1/mu per photon.  The direct beam is left out (path.c's next-event
 * estimate counts it; under such a deck it is below 1e-6 of the sun).
 *
 * The base is a shell: a view far from the observer meets it where the sun stands a little higher
 * or lower, so the coefficients are made at DECK_SUN_NODES local sun zenith angles spanning those
 * the paths can reach, and interpolated. */
#ifndef FM_TRANSPORT_DECK_BASE_H
#define FM_TRANSPORT_DECK_BASE_H

#include "atmosphere/atmosphere.h"
#include "base/vec.h"
#include "transport/free_flight.h"
#include "firmament/firmament.h"
#include "sky.h"

#include <stdint.h>

#define DECK_MU_TERMS 3 /* 1, sqrt(mu), mu */
#define DECK_AZ_TERMS 1 /* cos(m phi), m = 0 only */
#define DECK_TERMS (DECK_MU_TERMS * DECK_AZ_TERMS)
#define DECK_SUN_NODES 2

typedef struct deck_base {
    double base_radius_m;
    int K, nodes;
    double theta0, dtheta;               /* node i at local sun zenith angle theta0 + i dtheta (rad) */
    double basis[DECK_MU_TERMS][DECK_MU_TERMS]; /* B_j(mu) = sum_i basis[j][i] mu^(i/2) */
    double *coef;                        /* [node][K][DECK_TERMS], W m^-2 sr^-1 nm^-1 */
} deck_base;

/* The base of the deck at base_altitude_m in atm for local sun zenith angles from theta_lo to
 * theta_hi (rad, < pi/2), from `photons` photons per angle and wavelength.  FM_ERR_OUT_OF_MEMORY
 * leaves nothing to free; a cancelled build returns FM_ERR_CANCELLED. */
fm_status deck_base_build(deck_base *d, const atmosphere *atm, double base_altitude_m, double theta_lo,
                          double theta_hi, int photons, uint64_t seed, int threads, const atomic_int *cancel);
void deck_base_free(deck_base *d);

/* The base's radiance (every grid wavelength) seen from below at the point x of the base shell
 * looking up along the unit vector dir, with the sun toward sun_dir, times `scale`, added to L. */
void deck_base_radiance(const deck_base *d, vec3 x, vec3 dir, vec3 sun_dir, double scale, double *L);

/* The sky's deck base for the fast path's paths, when it applies: a layer of SKY_TRUNCATE_TAU or
 * more (the lowest such layer's base), the observer below it and the sun DECK_MIN_SUN_DEG or more
 * up; traced in the sky's truncated copy (sky_scattering_media), for the local sun zenith angles of
 * the base the observer's paths can reach.  *built is 0 (and d untouched) where it does not apply. */
#define DECK_MIN_SUN_DEG 5.0
fm_status deck_base_for_sky(deck_base *d, const fm_sky *sky, int photons, uint64_t seed, int threads,
                            const atomic_int *cancel, int *built);

/* Ends seg at the deck's base when it reaches it (it does not hit the ground and d is not NULL; a
 * segment from below the base): returns 1 then, else 0 with seg unchanged. */
int deck_base_cut(const deck_base *d, ray_segment *seg);

#endif

/* A homogeneous cloud layer as a custom atmosphere file and the estimators measured on it, shared by
 * test_thick_media.c and bench/thick_media.c (issue 48).
 *
 * The layer: one Henyey-Greenstein constituent between 1 and 2 km (ramps of one 50 m profile cell at
 * each edge; for a layer of uniform albedo and phase function only the optical depth matters, so the
 * ramps change nothing), clear air below and up to the top at 3 km, solar irradiance 1, on a planet
 * of radius 10^6 km so that the sphere is a plane to 1e-6 over the kilometres a path wanders. */
#ifndef FM_TEST_THICK_MEDIA_CASES_H
#define FM_TEST_THICK_MEDIA_CASES_H

#include "adding_doubling.h"
#include "firmament/firmament.h"
#include "sky.h"

#include <stdint.h>

#define CLOUD_SUN_ELEVATION 30.0

typedef struct cloud {
    double tau, g, ssa, albedo;
} cloud;

/* The sky of the cloud seen from altitude_m (below 3000); *path receives the file (drop_cloud_sky
 * removes it). */
fm_sky *cloud_sky(const cloud *c, double altitude_m, char **path);
void drop_cloud_sky(fm_sky *sky, char *path);

/* Adding-doubling for the cloud at view cosines mu (16 streams, 32 below tau 5; delta-M). */
ad_solution cloud_reference(const cloud *c, int n_mu, const double *mu);

/* pi times the mean radiance over N cosine-weighted directions about +Z (up = 1) or -Z (up = -1)
 * from the sky's observer by the reference estimator: the hemispherical irradiance; *se its standard
 * error. */
double cloud_irradiance(const fm_sky *sky, double up, int N, uint64_t seed, double *se);

#endif

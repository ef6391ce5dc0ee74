/* Guided free flights across the Earth's shadow, for deep twilight.
 *
 * With the sun well below the horizon (twilight.h says from when), the air near the observer is in
 * the shadow and the light it scatters comes from sunlit air hundreds of kilometres off, high up,
 * toward the sun.  How much light a point receives climbs by orders of magnitude with altitude and
 * toward the sun (sun -18: the single-scattering radiance averaged over a point's sky is 1e-12 of
 * its daytime value at the ground under the observer, 2e-7 at 30 km and 5e-6 at 30 km 300 km
 * toward the sun).  Delta tracking puts a path's vertices where the air is dense, low down, and
 * the rare path that reaches a bright point brings most of a table node's value: at sun -18 one
 * path in 32 768 carried 30-94% of a node's second moment.
 *
 * This places a segment's next vertex by a density proportional to
 *     sigma_s(t) T(0, t) I(x_t),
 * I the single-scattering luminance averaged over all directions at x_t (the light the vertex will
 * pass on), tabulated here by altitude and local sun elevation (the atmosphere is horizontally
 * homogeneous).  The density is piecewise constant on cells of the segment, from the integrand at
 * their ends at one wavelength (the same for every hero wavelength, so the path's spectral MIS
 * weights are unchanged), mixed with the same cells' sigma_s T alone (the physical density, so that
 * a dark vertex still gets a bounded weight) and a uniform floor (positive wherever the integrand
 * can be).  A segment that ends on the ground reaches it with the probability T at that
 * wavelength, kept within [0.05, 0.7]; one that leaves through the top always scatters (a forced
 * collision).  Every
 * wavelength's weight is then its own sigma_s T / pdf, exactly: the estimator stays unbiased
 * whatever I is; I only decides where the samples go. */
#ifndef FM_TRANSPORT_SHADOW_FLIGHT_H
#define FM_TRANSPORT_SHADOW_FLIGHT_H

#include "base/rng.h"
#include "base/units.h"
#include "base/vec.h"
#include "transport/free_flight.h"
#include "transport/path_context.h"


#define SHADOW_FLIGHT_LEVELS 20 /* altitudes, 0 to 100 km */
#define SHADOW_FLIGHT_SUNS 26   /* local sun elevations, from the observer's up, SHADOW_FLIGHT_SUN_STEP apart */
#define SHADOW_FLIGHT_SUN_STEP (1.0 * FM_DEG) /* rad */
#define SHADOW_FLIGHT_TOP_KM 100

typedef struct shadow_flight_table {
    double bottom_radius;                                        /* m */
    double sun0, sun_step;                                       /* rad: column 0 is the observer's */
    double value[SHADOW_FLIGHT_LEVELS][SHADOW_FLIGHT_SUNS];      /* I, CIE Y-weighted (or the one value) */
    double ambient[SHADOW_FLIGHT_LEVELS]; /* I scattered once more, above the observer (below) */
    unsigned char level_at_km[SHADOW_FLIGHT_TOP_KM + 1]; /* the level below each whole km, a first guess */
} shadow_flight_table;

/* The altitudes of the levels (km above the ground). */
extern const double shadow_flight_level_km[SHADOW_FLIGHT_LEVELS];

/* I at radius r (m) and local sun cosine mu_s: bilinear, clamped to the table. */
double shadow_flight_light(const shadow_flight_table *t, double r, double mu_s);

/* The light of orders 1 and 2 at radius r (m) and local sun cosine mu_s: I plus the ambient at that
 * altitude (tabulated above the observer, used wherever the point is).  The ambient is the light of
 * order 2 that a point in the shadow receives, which I leaves out: at sun -18 single scattering gives
 * 6e-13 of daylight at the ground below the observer, I scattered once more 2e-9.  Per level, the
 * sphere average of the integral of sigma_s T I along each direction (isotropic scattering, the same
 * rows and columns as I, 48 points per ray): an order of magnitude for Russian roulette (path.c),
 * nothing is counted from it. */
double shadow_flight_light_and_ambient(const shadow_flight_table *t, double r, double mu_s);

/* The light of order 2 seen from origin along dir: I scattered once more along that ray (isotropic
 * scattering, sigma_s T at the grid's middle wavelength, 16 points), in I's units.  For the sky
 * guide (sky_guide.h): in the shadow it outweighs single scattering, which is all the guide had. */
double shadow_flight_order2(const shadow_flight_table *t, const path_context *single, vec3 origin, vec3 dir);

/* sigma_s T I at the middle wavelength integrated along seg from its origin (trapezoids on `points`
 * + 1 points crowded at the origin, where a low point's air is densest). */
double shadow_flight_light_along(const shadow_flight_table *t, const path_context *single, const ray_segment *seg,
                                 int points);

/* The next interaction on seg: returns 1 for a scattering at *t_out, 0 for the ground (at seg's end),
 * after multiplying w[k] by that event's f/p for every grid wavelength. */
int shadow_flight(const path_context *ctx, const shadow_flight_table *table, const ray_segment *seg, rng *r,
                  double *w, double *t_out);

#endif

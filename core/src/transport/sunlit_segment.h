/* Direct sunlight along a path segment, by its expected value ("line-integral" next-event
 * estimation), for paths that cross the Earth's shadow.
 *
 * A path that leaves a vertex x in direction d gets, from its next interaction on the segment
 * [0, t_end] (air or the ground at its end), the sunlight
 *     S_k = integral_0^t_end T_k(x, x_t) sigma_s,k(x_t) p_k(d . s; x_t) E0_k Tbar_k(x_t) dt
 *           + [segment ends on the ground] T_k(x, x_g) albedo_k / pi E0_k Tbar_hor,k(x_g),
 * x_t = x + t d, Tbar the disk-integrated sun transmittance table.  Point next-event estimation at
 * the collision that delta tracking finds estimates the same quantity; at twilight that collision
 * lies almost always in the Earth's shadow (estimate 0), and rarely in the sunlit air above it
 * (estimate huge).  Here S is estimated directly instead:
 *  - the part of the segment in the umbra (no point of the disk above the horizon, Tbar = 0) is
 *    computed in closed form and left out; it is a single interval, the umbra being convex;
 *  - on the sunlit rest, a proxy of the integrand (three wavelengths) at 9 points (5 for rising
 *    segments, path.h) gives a density that is exponential within each cell between its ends
 *    (constant, at the larger end, next to a peak or the dark), mixed with a uniform one so that it
 *    is positive wherever the integrand can be; two stratified samples of it are evaluated at every
 *    wavelength;
 *  - the density is the same for every wavelength, so the path's spectral MIS weights are
 *    unchanged, and the transmittance from x comes from the column table (no random numbers).
 * The path then goes on by delta tracking as before, without the point estimate at its next
 * interaction: that order is already counted. */
#ifndef FM_TRANSPORT_SUNLIT_SEGMENT_H
#define FM_TRANSPORT_SUNLIT_SEGMENT_H

#include "base/rng.h"
#include "transport/free_flight.h"
#include "transport/path_context.h"

/* Species columns from a segment's origin to distance t along it, from the column table (to the top
 * of the atmosphere) as a difference of two lookups; by quadrature where the table cannot: a ray
 * grazing the ground, and a segment that meets cloud or fog, whose column the table's bilinear
 * lookup misses by tenths of an optical depth (it bends at the layer's edges and with the direction). */
typedef struct segment_columns {
    const path_context *ctx;
    const ray_segment *seg;
    int reversed, ok, dense;
    double start[FM_MAX_SPECIES];
} segment_columns;

void segment_columns_init(segment_columns *sc, const path_context *ctx, const ray_segment *seg);
void segment_columns_at(const segment_columns *sc, double t, double *col);

/* The same for the optical depth at the middle wavelength alone (path_context.mid_depth), from its
 * one-wavelength table: what the deep-twilight flights' density needs (shadow_flight.c). */
typedef struct segment_depth {
    const path_context *ctx;
    const ray_segment *seg;
    int reversed, ok;
    double start; /* from the origin to the top, along the segment or (reversed) against it */
} segment_depth;

void segment_depth_init(segment_depth *sd, const path_context *ctx, const ray_segment *seg);
double segment_depth_at(const segment_depth *sd, double t);

/* The part [*t0, *t1] of [0, seg->t_end] inside the Earth's umbra; 0 when the segment does not
 * enter it (or only grazes it).  The interval may be a little shorter than the true one, never
 * longer: both ends are checked against the sun table's own shadow test. */
int segment_umbra(const path_context *ctx, const ray_segment *seg, double *t0, double *t1);

/* Adds to S[k] (all grid wavelengths, W m^-2 sr^-1 nm^-1 per unit path weight) an unbiased
 * estimate of S_k for the segment whose umbra is [u0, u1] (segment_umbra). */
void segment_sunlight(const path_context *ctx, const ray_segment *seg, double u0, double u1, rng *r, double *S);

#endif

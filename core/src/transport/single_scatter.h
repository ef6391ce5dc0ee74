/* Deterministic quadrature of order-1 radiance (no random numbers):
 *     L1(x, w) = integral_0^t_end T(0, t) sum_c sigma_s,c(t) p_c(w . s) E0 Tbar(x_t, s) dt
 *              + [ground hit] T(0, t_end) albedo / pi E0 Tbar_horizontal(ground)
 * along the view ray, with Gauss-Legendre on pieces between altitude breakpoints (subdivided so that
 * no piece is optically thick), the view transmittance from nested quadratures of the species
 * columns, and the sun from the same table the path tracer uses.  It is the fast path's single
 * scattering; the path tracer restricted to order 1 estimates the same integral.  When the context
 * carries a ground_irradiance table, the ground term also reflects that diffuse irradiance.
 *
 * The integral splits into the view ray's part (quadrature points, their radii, densities and view
 * optical depths: a function of the ray's elevation alone) and the sun's part (phase and sunlight at
 * each point: a function of the angle to the sun).  Every direction of one elevation seen from one
 * point shares the first, so a table row computes it once (single_scatter_ray) and evaluates only
 * the second per azimuth: 3x less work for the single-scattering table. */
#ifndef FM_TRANSPORT_SINGLE_SCATTER_H
#define FM_TRANSPORT_SINGLE_SCATTER_H

#include "transport/path_context.h"

/* The view ray's part of L1 from `origin` at one elevation. */
typedef struct single_scatter_ray {
    vec3 origin;
    int n;            /* quadrature points */
    int hits_ground;
    double t_end;     /* distance to the ground (or the top) */
    double *point;    /* [n][3 + C + K]: t (m), weight (m), radius (m), densities, view optical depths */
    const sun_irradiance *sun_table; /* the path context's at init (NULL: none) */
    sun_row_place *sun_row; /* [n]: the radius's place in sun_table, for its lookup per direction */
    double ground_transmittance[FM_MAX_WAVELENGTHS]; /* exp(-view optical depth) to the ground, once per ray */
} single_scatter_ray;

/* Fills the view ray's part for the ray from origin along dir with `points` Gauss-Legendre nodes
 * per piece (6 in single_scatter_radiance; docs/decisions/2026-12-06-quadrature-accuracy.md);
 * FM_ERR_OUT_OF_MEMORY on failure. */
fm_status single_scatter_ray_init(single_scatter_ray *ray, const path_context *ctx, vec3 origin, vec3 dir,
                                  int points);
void single_scatter_ray_free(single_scatter_ray *ray);

/* Adds L1 (per grid wavelength) for direction dir, which must have the elevation of the ray's
 * direction (any azimuth), to L. */
void single_scatter_ray_radiance(const single_scatter_ray *ray, const path_context *ctx, vec3 dir, double *L);

/* Adds L1 (per grid wavelength) for the ray from origin in direction dir to L (one ray: both
 * parts, 6 points per piece). */
void single_scatter_radiance(const path_context *ctx, vec3 origin, vec3 dir, double *L);

#endif

/* First scattering vertices of a table node's paths, placed along its view ray by stratified
 * sampling instead of by delta tracking.
 *
 * The multiple-scattering radiance toward the observer is
 *     L_ms,k = integral_0^t_end sigma_s,k(t) T_k(0, t) J_k(x_t) dt,
 * J_k the in-scattered radiance of orders >= 1 at x_t.  Each of a node's N paths places its first
 * vertex at t from a piecewise-constant density over 64 cells along the ray (crowded at the
 * observer), proportional to sigma_s T at three wavelengths (a share of it spread by length so
 * that it is positive everywhere: 1/25 by day, 1/6 at twilight), with its uniform number
 * stratified over the N paths: (p + u) / N.
 * The vertex's spectral weight is sigma_s,k(t) T_k(0, t) / pdf(t), T from the column table; the
 * density is the same for every wavelength.  Delta tracking would place the vertices by the same
 * law, but at random: at twilight, where the little light there is reaches the vertices high on
 * the ray, that randomness was most of the noise. */
#ifndef FM_TRANSPORT_VIEW_RAY_VERTICES_H
#define FM_TRANSPORT_VIEW_RAY_VERTICES_H

#include "transport/free_flight.h"
#include "transport/path.h"
#include "transport/sunlit_segment.h"

#define VIEW_RAY_CELLS 64

typedef struct view_ray_vertices {
    ray_segment seg;
    segment_columns columns;         /* species columns along seg (points at seg: do not copy) */
    double edge[VIEW_RAY_CELLS + 1]; /* cell edges, distances along the ray (m) */
    double cdf[VIEW_RAY_CELLS + 1];
} view_ray_vertices;

/* Sets up the density for the ray from origin along dir, in place (the struct refers to itself);
 * 0 when the ray crosses no air. */
int view_ray_vertices_init(view_ray_vertices *v, const path_context *ctx, vec3 origin, vec3 dir);

/* The vertex for the uniform number u in [0, 1): its position and spectral weights. */
vec3 view_ray_vertex(const view_ray_vertices *v, const path_context *ctx, double u, double *weight);

#endif

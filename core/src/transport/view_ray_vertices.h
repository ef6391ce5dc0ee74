/* First scattering vertices of a table node's paths, placed along its view ray by stratified
 * sampling instead of by delta tracking.
 *
 * The multiple-scattering radiance toward the observer is
 *     L_ms,k = integral_0^t_end sigma_s,k(t) T_k(0, t) J_k(x_t) dt,
 * J_k the in-scattered radiance of orders >= 1 at x_t.  Each of a node's N paths places its first
 * vertex at t from a piecewise-constant density over 64 cells along the ray (crowded at the
 * observer), proportional to sigma_s T at three wavelengths (a share of it spread by length so
 * that it is positive everywhere: 1/25 by day, 1/6 at twilight), with its uniform number
 * stratified over the N paths: (p + u) / N.  In deep twilight (path_context's
 * first_vertex_light_share) part of the rest is sigma_s T times the light of orders 1 and 2 at the
 * cell's middle (shadow_flight_light_and_ambient), which climbs with altitude far faster than the
 * air thins.
 * The vertex's spectral weight is sigma_s,k(t) T_k(0, t) / pdf(t); the density is the same for
 * every wavelength.  T comes from the species' columns along the ray, summed cell by cell by
 * quadrature once per ray and completed within the vertex's cell: the column table's difference
 * of two columns to the top (which the paths' segments still take, sunlit_segment.h) loses the
 * short path of a ray near the horizon between two long ones, and made the urban sunset's horizon
 * 0.8% too dark (its rows 128; 0.3% at 256, 0.1% at 512).  Delta tracking would place the
 * vertices by the same law, but at random: at twilight, where the little light there is reaches
 * the vertices high on the ray, that randomness was most of the noise. */
#ifndef FM_TRANSPORT_VIEW_RAY_VERTICES_H
#define FM_TRANSPORT_VIEW_RAY_VERTICES_H

#include "transport/free_flight.h"
#include "transport/path_context.h"

#define VIEW_RAY_CELLS 64

typedef struct view_ray_vertices {
    ray_segment seg;
    double edge[VIEW_RAY_CELLS + 1]; /* cell edges, distances along the ray (m) */
    double column[VIEW_RAY_CELLS + 1][FM_MAX_SPECIES]; /* species columns from the origin to each edge */
    double cdf[VIEW_RAY_CELLS + 1];
    /* In deep twilight, sum over the cells of sigma_s T (three wavelengths) x the light of orders 1
     * and 2 at the cell's middle x its length: up to a constant, the ray's radiance of orders 2
     * and 3 were that light isotropic (the table's fit divides by it, sky_grid_fit.h); else 0. */
    double light_integral;
    int at_deck; /* the ray ends at a deck's base (path_context.deck) */
} view_ray_vertices;

/* Sets up the density for the ray from origin along dir; 0 when the ray crosses no air. */
int view_ray_vertices_init(view_ray_vertices *v, const path_context *ctx, vec3 origin, vec3 dir);

/* The species' columns from the origin to the point t of the ray, 0 <= t <= seg.t_end. */
void view_ray_columns(const view_ray_vertices *v, const atmosphere *atm, double t, double *col);

/* The vertex for the uniform number u in [0, 1): its position and spectral weights. */
vec3 view_ray_vertex(const view_ray_vertices *v, const path_context *ctx, double u, double *weight);

#endif

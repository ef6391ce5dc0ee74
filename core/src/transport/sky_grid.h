/* The fast path's radiance table over view directions.
 *
 * Seen from one point of a horizontally homogeneous atmosphere, radiance depends only on the view
 * elevation e and the azimuth relative to the sun phi, and is symmetric about the sun's vertical
 * plane: phi in [0, pi] suffices.  The table has two domains that meet at the horizon elevation e_h
 * (below 0 for an observer above the ground), where radiance jumps from sky to ground:
 *     sky rows:    e = e_h + (pi/2 - e_h) u^2,  u = row / (rows_sky - 1)     (row 0 at the horizon)
 *     ground rows: e = e_h - (pi/2 + e_h) u^2,  u = row / (rows_ground - 1)
 * so rows crowd where radiance changes fastest; columns are uniform in phi.  Lookups interpolate
 * bilinearly in (u, phi) within the domain of the direction: in the values themselves, or, for a
 * logarithmic grid, in their logarithms (exact for radiance that falls exponentially across the
 * grid, as through the limb seen from high up; meant for deterministic, non-negative values). */
#ifndef FM_TRANSPORT_SKY_GRID_H
#define FM_TRANSPORT_SKY_GRID_H

#include "firmament/firmament.h"

typedef struct sky_grid {
    double horizon_elevation; /* rad */
    int rows_sky, rows_ground, cols, channels;
    int logarithmic;          /* values hold log(max(v, FM_GRID_FLOOR)) */
    float *values;            /* [rows_sky + rows_ground][cols][channels], sky rows first */
} sky_grid;

#define FM_GRID_FLOOR 1e-30f

fm_status sky_grid_init(sky_grid *g, double horizon_elevation, int rows_sky, int rows_ground, int cols,
                        int channels, int logarithmic);

/* Stores value v at node `index`, channel c. */
void sky_grid_set(sky_grid *g, int index, int c, float v);
void sky_grid_free(sky_grid *g);

/* The zenith row (top sky row) and the nadir row (last ground row) each hold one direction in every
 * column: replaces their columns by the columns' mean, so independent Monte Carlo estimates of the
 * same radiance pool into one (no azimuthal spokes at the zenith of a fisheye). */
void sky_grid_average_poles(sky_grid *g);

static inline int sky_grid_nodes(const sky_grid *g) { return (g->rows_sky + g->rows_ground) * g->cols; }

/* View elevation and relative azimuth (rad) of node `index` (row-major over all rows). */
void sky_grid_node_angles(const sky_grid *g, int index, double *elevation, double *rel_azimuth);

/* Weights w[i] of the sky's nodes (the first rows_sky x cols, row-major) such that, for the table's
 * interpolant L, sum_i w[i] v_i = integral over the sky domain of L(omega) sin(elevation) d omega,
 * both azimuthal halves: the irradiance the sky's radiance puts on a horizontal surface at the
 * observer.  Meant for a horizon at elevation 0 (an observer on the ground), where the weights
 * sum to pi.  (A linear table: not for logarithmic grids.) */
void sky_grid_irradiance_weights(const sky_grid *g, double *w);

/* Interpolated value at (elevation, relative azimuth in [0, pi]). */
void sky_grid_lookup(const sky_grid *g, double elevation, double rel_azimuth, float *out);

/* Its channel c alone (the same value as sky_grid_lookup's). */
double sky_grid_lookup_channel(const sky_grid *g, double elevation, double rel_azimuth, int c);

#endif

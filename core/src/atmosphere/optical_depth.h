/* Optical depth along rays in the spherical shell.
 *
 * A ray starts at radius r with direction cosine mu (to the local zenith).  With impact parameter
 * p = r sqrt(1 - mu^2) and s = t + r mu (signed distance from the point closest to the centre), the
 * radius along the ray is sqrt(p^2 + s^2).  Columns are particle counts per m^2 along the ray for
 * each species; optical depth is sum_c sigma_c * column_c (atmosphere_optical_depth).
 *
 * Three ways to get a column, for three needs:
 * - column_exact: closed form per 50 m cell of the piecewise-linear profile (the density is
 *   linear in r within a cell and the integral of r / sqrt(r^2 - p^2) is elementary); exact to
 *   rounding, slow; used by tests and to check the others.
 * - column_quadrature: Gauss-Legendre on pieces between fixed altitude breakpoints and the
 *   profiles' edges; within 3e-5 of the closed form for 99% of rays (optical_depth.c), fast; used to
 *   build tables, along view rays and for the sun disk seen through the air.
 * - column_table_lookup: bilinear table of the column from (r, mu) to the top of the atmosphere,
 *   parametrised as in E. Bruneton's precomputed atmospheric scattering (2017) so the horizon is
 *   resolved, with rows on the aerosol layers' edges (table_rows.h); used for the transmittance
 *   toward the sun and along paths' segments. */
#ifndef FM_ATMOSPHERE_OPTICAL_DEPTH_H
#define FM_ATMOSPHERE_OPTICAL_DEPTH_H

#include "atmosphere/atmosphere.h"
#include "atmosphere/table_rows.h"

/* Distance from (r, mu) to the top of the atmosphere along the ray (r <= top). */
double ray_distance_to_top(const atmosphere *atm, double r, double mu);
/* Whether the ray from (r, mu) hits the ground. */
int ray_hits_ground(const atmosphere *atm, double r, double mu);
/* Distance to the ground (only meaningful when ray_hits_ground). */
double ray_distance_to_ground(const atmosphere *atm, double r, double mu);
/* Distance to where the ray leaves the atmosphere: the ground or the top. */
double ray_distance_to_boundary(const atmosphere *atm, double r, double mu, int *hits_ground);
/* Cosine of the zenith angle of the horizon seen from radius r (<= 0). */
double horizon_mu(const atmosphere *atm, double r);

/* Columns of every species along [0, t_max] of the ray. */
void column_exact(const atmosphere *atm, double r, double mu, double t_max, double *columns);
void column_quadrature(const atmosphere *atm, double r, double mu, double t_max, double *columns);

/* Breakpoints of the quadrature: the ray's crossings of fixed altitudes, the ray's turning point
 * and its ends.  Fills s[] (increasing, including s0 and s1) and returns the count. */
int ray_pieces(const atmosphere *atm, double r, double mu, double t_max, double *s, int max_count);

typedef struct column_table {
    table_rows rows; /* the radii */
    int n_mu, species;
    float *columns; /* [i_r][i_mu][c], particles m^-2 */
} column_table;

/* n_r rows uniform in x_r and the edges' rows (table_rows.h), n_mu directions each. */
fm_status column_table_build(column_table *table, const atmosphere *atm, int n_r, int n_mu, int threads,
                             fm_error *err);
void column_table_free(column_table *table);
/* Columns from (r, mu) to the top; returns 0 (and leaves columns unset) if the ray hits the ground. */
int column_table_lookup(const column_table *table, const atmosphere *atm, double r, double mu, double *columns);
/* column_table_lookup in two steps, for loops over many points: the cell of (r, mu) (ok 0 where the
 * ray hits the ground), its nodes asked of memory ahead of their reading; then its columns, the same. */
typedef struct column_cell {
    size_t node;   /* the first node, i_r n_mu + i_mu */
    double tr, tm; /* the bilinear weights of the next row and direction */
    int ok;
} column_cell;
void column_table_cell(const column_table *table, const atmosphere *atm, double r, double mu, column_cell *cell);
void column_table_cell_columns(const column_table *table, const column_cell *cell, double *columns);

/* One wavelength's optical depth to the top (sum over species of sigma_t(k) x column) on a column
 * table's nodes, bilinear the same way: 1 / species of its memory.  The deep-twilight flights'
 * density (shadow_flight.c) needs no more than that at 25 points per segment, and this table stays
 * in cache where the whole column table does not (docs/decisions/2026-12-06-random-numbers-and-lookups.md). */
typedef struct depth_table {
    const column_table *grid; /* its rows and directions */
    int k;                    /* the wavelength's index */
    float *depth;             /* [i_r][i_mu] */
} depth_table;

fm_status depth_table_build(depth_table *t, const column_table *columns, const atmosphere *atm, int k, fm_error *err);
void depth_table_free(depth_table *t); /* accepts a zeroed table */
/* The depth from (r, mu) to the top; returns 0 (and leaves depth unset) if the ray hits the ground. */
int depth_table_lookup(const depth_table *t, const atmosphere *atm, double r, double mu, double *depth);

#endif

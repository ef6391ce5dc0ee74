/* Direct sunlight inside the atmosphere, tabulated once per sky (as lookups need it).
 *
 * At a point at radius r, with the sun's centre at zenith cosine mu_s, the disk-averaged
 * transmittance for grid wavelength k is
 *     Tbar_k(r, mu_s) = sum_j w_jk exp(-tau_k(r, mu_j)),
 * the chord quadrature of sun/sun_disk.h over the part of the disk above the horizon (the Earth's
 * occlusion gives the penumbra at sunset), tau_k from the column table.  The direct irradiance on a
 * surface facing the sun is E0_k Tbar_k; on a horizontal surface the same with each chord weighted
 * by its own cosine.  Tables are over (x_r, x_mu) with x_r as in the column table and
 *     mu_s = mu_lo(r) + (1 - mu_lo(r)) x_mu^2,  mu_lo = cos(theta_horizon(r) + sun radius),
 * which packs nodes where the sun sets for that altitude.  The rows are the column table's
 * (table_rows.h), with rows at the aerosol layers' edges. */
#ifndef FM_ATMOSPHERE_SUN_IRRADIANCE_H
#define FM_ATMOSPHERE_SUN_IRRADIANCE_H

#include "atmosphere/atmosphere.h"
#include "atmosphere/optical_depth.h"
#include "sun/sun_disk.h"

#include <stdatomic.h>

/* Nodes are computed on first use, SUN_BLOCK of a row at a time: the paths of one render meet a
 * band of local sun elevations around the observer's, so most of the table is never read
 * (docs/decisions/2026-12-06-sampling-densities.md).  A lookup builds the blocks it reads, on
 * whichever thread reads them first. */
#define SUN_BLOCK 16

/* The few wavelengths whose depths a segment's sunlight proxy reads at every cell end
 * (sunlit_segment.c): a quarter, half and three quarters along the grid (or all, for fewer than
 * SUN_FEW).  They are kept side by side as well (sun_irradiance.few), so that a lookup of them reads
 * one cache line per corner, not one per wavelength spread over the whole table
 * (docs/decisions/2026-12-07-live-build-cost.md). */
#define SUN_FEW 3
int sun_irradiance_few_wavelengths(int K, int ks[SUN_FEW]);

typedef struct sun_irradiance {
    table_rows rows;   /* the radii, as the column table's */
    int n_mu, count;
    float *normal;     /* [i_r][i_mu][k] Tbar_k */
    float *horizontal; /* [i_mu][k] the same times the cosine to the local zenith, on the ground only */
    float *few;        /* [i_r][i_mu][j] normal's values at the few wavelengths (SUN_FEW), j of few_count */
    int few_k[SUN_FEW], few_count;
    double *mu_lo;     /* [i_r] mu_lo of the row's radius (lookups need it for two rows each time) */
    double *per_mu_span; /* [i_r] 1 / (1 - mu_lo): a lookup multiplies, it does not divide */
    unsigned char *dense_cell; /* [i_r] whether the cell from row i_r up holds cloud or fog */
    /* what the nodes are built from, and each block's state (empty, being built, ready) */
    const atmosphere *atm;
    const column_table *columns;
    const sun_disk *sun;
    int blocks_per_row;
    atomic_uchar *block_state; /* [i_r][block] */
} sun_irradiance;

/* Evaluates Tbar (and its horizontal counterpart, may be NULL) directly: optical depths from the
 * column table, or integrated along each ray when columns is NULL (slower, for one-off values). */
void sun_transmittance_direct(const atmosphere *atm, const column_table *columns, const sun_disk *sun,
                              double r, double mu_s, double *normal, double *horizontal);

/* Sets the table up over n_r x n_mu nodes (built as lookups need them); atm, columns and sun must
 * outlive it. */
fm_status sun_irradiance_build(sun_irradiance *table, const atmosphere *atm, const column_table *columns,
                               const sun_disk *sun, int n_r, int n_mu, fm_error *err);
void sun_irradiance_free(sun_irradiance *table);

/* Bilinear lookup of Tbar_k(r, mu_s) for all k. */
void sun_irradiance_lookup(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun, double r,
                           double mu_s, double *normal);

/* The same on the ground, with the horizontal counterpart (the only radius the table holds it for:
 * horizontal surfaces are on the ground). */
void sun_irradiance_lookup_ground(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                  double mu_s, double *normal, double *horizontal);

/* The same as optical depths, -ln Tbar_k (infinite where Tbar is 0), for callers that multiply Tbar
 * by another transmittance: one exp of the summed depths instead of two.  Returns 0 when the point
 * is in the Earth's shadow (every depth infinite), so callers can skip it. */
int sun_irradiance_lookup_depth(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun, double r,
                                 double mu_s, double *depth);

/* Where radius r lies between the table's rows: for many lookups at one radius (the points of a
 * view ray, each read for many directions), sun_irradiance_lookup_depth_at then finds only mu_s. */
typedef struct sun_row_place {
    int row;  /* the row at or below r */
    double t; /* the fraction toward the row above */
} sun_row_place;
sun_row_place sun_irradiance_row_place(const sun_irradiance *table, const atmosphere *atm, double r);

/* sun_irradiance_lookup_depth at r, whose place is `place` (sun_irradiance_row_place(r)): the same. */
int sun_irradiance_lookup_depth_at(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                   sun_row_place place, double r, double mu_s, double *depth);

/* sun_irradiance_lookup_depth_at in two steps, for loops over many points: the point's cell (its
 * nodes built, and asked of memory ahead of their reading), then its depths, the same. */
typedef struct sun_cell {
    double w[4];   /* the corners' bilinear weights */
    size_t idx[4]; /* and their offsets in normal */
    int dark;      /* in the Earth's shadow */
} sun_cell;
void sun_irradiance_cell_at(const sun_irradiance *table, sun_row_place place, double mu_s, sun_cell *cell);
int sun_irradiance_cell_depths(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                               const sun_cell *cell, double r, double mu_s, double *depth);
/* The cell of (r, mu_s), as sun_irradiance_cell_at of its row place; and sun_irradiance_lookup from
 * a cell: lookup(r, mu_s) is the two, the same. */
void sun_irradiance_cell(const sun_irradiance *table, const atmosphere *atm, double r, double mu_s, sun_cell *cell);
void sun_irradiance_cell_transmittances(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                        const sun_cell *cell, double r, double mu_s, double *normal);

/* The optical depths for the n grid wavelengths ks[0..n-1] only (depth[i] for ks[i]; infinite where
 * Tbar is 0); returns 0 in the Earth's shadow. */
int sun_irradiance_lookup_some_depths(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                      double r, double mu_s, int n, const int *ks, double *depth);

/* sun_irradiance_lookup_some_depths for the few wavelengths (sun_irradiance_few_wavelengths): the
 * same values, from the compact copy. */
int sun_irradiance_lookup_few_depths(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                     double r, double mu_s, double *depth);

/* sun_irradiance_lookup_few_depths in two steps, as sun_irradiance_cell_at and _cell_depths: the
 * cell of (r, mu_s), whose offsets are then the compact copy's, then the few depths, the same. */
void sun_irradiance_few_cell(const sun_irradiance *table, const atmosphere *atm, double r, double mu_s,
                             sun_cell *cell);
int sun_irradiance_few_cell_depths(const sun_irradiance *table, const sun_cell *cell, double *depth);

/* Whether the whole disk is below the horizon of radius r (the umbra): the table is 0 there, and
 * wherever this holds at the lower of the two table rows around r. */
int sun_in_umbra(const atmosphere *atm, const sun_disk *sun, double r, double mu_s);

#endif

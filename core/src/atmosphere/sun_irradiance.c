#include "atmosphere/sun_irradiance.h"

#include "base/exp_array.h"
#include "base/status.h"
#include "base/threads.h"
#include "base/units.h"
#include "base/vec.h"
#include "spectrum/spectral.h"

#include <math.h>
#include <sched.h>
#include <stdlib.h>

static double mu_low(const atmosphere *atm, const sun_disk *sun, double r)
{
    double theta_h = acos(horizon_mu(atm, r));
    return cos(fmin(FM_PI, theta_h + sun->angular_radius));
}

/* Above this elevation of its centre over the local horizon (rad) the disk takes the coarse
 * three-chord rule (sun_disk.coarse).  Against the 12-chord rule for clear air, urban and desert
 * dust at turbidity 3, at 0, 2 and 20 km: within 4e-5 from 4 degrees up (1.2e-4 at 2 degrees),
 * which is the column table's own interpolation error; 4 times fewer exps for most of the table. */
#define SUN_COARSE_ELEVATION (4.0 * FM_DEG)

void sun_transmittance_direct(const atmosphere *atm, const column_table *columns, const sun_disk *sun,
                              double r, double mu_s, double *normal, double *horizontal)
{
    const int K = atm->grid.count;
    for (int k = 0; k < K; k++) {
        normal[k] = 0.0;
        if (horizontal)
            horizontal[k] = 0.0;
    }
    double theta_s = acos(clamp_cosine(mu_s));
    double theta_h = acos(horizon_mu(atm, r));
    /* the disk's centre this far above the local horizon: the coarse rule, the full one, or the
     * part of the disk above the horizon */
    double elevation = theta_h - theta_s;
    sun_chord_rule cut;
    const sun_chord_rule *rule = elevation >= SUN_COARSE_ELEVATION ? &sun->coarse : &sun->full;
    if (elevation < sun->angular_radius) {
        sun_chord_rule_above(sun, K, -elevation, &cut);
        rule = &cut;
    }
    double col[FM_MAX_SPECIES], T[FM_MAX_WAVELENGTHS];
    for (int j = 0; j < rule->n; j++) {
        double mu_j = cos(theta_s - rule->delta[j]);
        if (columns) {
            if (!column_table_lookup(columns, atm, r, mu_j, col))
                continue;
        } else {
            if (ray_hits_ground(atm, r, mu_j))
                continue;
            column_quadrature(atm, r, mu_j, ray_distance_to_top(atm, r, mu_j), col);
        }
        atmosphere_transmittances(atm, col, T);
        for (int k = 0; k < K; k++) {
            double t = rule->weight[j][k] * T[k];
            normal[k] += t;
            if (horizontal)
                horizontal[k] += t * mu_j;
        }
    }
}

/* The tables hold the effective optical depth -ln(Tbar), which is far smoother than Tbar itself
 * (exponentials of steep functions near the horizon); depths beyond MAX_DEPTH mean darkness. */
#define MAX_DEPTH 200.0

/* The depths -ln(t) of K transmittances in place, MAX_DEPTH for the dark ones (the logs in vector
 * lanes). */
static void to_depths(double *t, int K)
{
    const double darkest = exp(-MAX_DEPTH);
    int dark[FM_MAX_WAVELENGTHS];
    for (int k = 0; k < K; k++) {
        dark[k] = !(t[k] > darkest);
        if (dark[k])
            t[k] = 1.0;
    }
    log_array(t, t, K);
    for (int k = 0; k < K; k++)
        t[k] = dark[k] ? MAX_DEPTH : -t[k];
}

int sun_irradiance_few_wavelengths(int K, int ks[SUN_FEW])
{
    int n = K < SUN_FEW ? K : SUN_FEW;
    for (int i = 0; i < n; i++)
        ks[i] = K < SUN_FEW ? i : K * (i + 1) / 4;
    return n;
}

/* Node imu of row ir (and its horizontal counterpart on the ground row). */
static void build_node(const sun_irradiance *t, int ir, int imu)
{
    double normal[FM_MAX_WAVELENGTHS], horizontal[FM_MAX_WAVELENGTHS];
    double r = table_rows_radius(&t->rows, t->atm, ir);
    double lo = t->mu_lo[ir];
    double x = (double)imu / (t->n_mu - 1);
    double mu_s = lo + (1.0 - lo) * x * x;
    size_t i = (size_t)ir * t->n_mu + imu;
    /* horizontal surfaces are on the ground: the first row only */
    sun_transmittance_direct(t->atm, t->columns, t->sun, r, mu_s, normal, ir == 0 ? horizontal : NULL);
    to_depths(normal, t->count);
    for (int k = 0; k < t->count; k++)
        t->normal[i * t->count + k] = (float)normal[k];
    for (int j = 0; j < t->few_count; j++)
        t->few[i * SUN_FEW + j] = (float)normal[t->few_k[j]];
    if (ir == 0) {
        to_depths(horizontal, t->count);
        for (int k = 0; k < t->count; k++)
            t->horizontal[i * t->count + k] = (float)horizontal[k];
    }
}

enum { BLOCK_EMPTY, BLOCK_BUILDING, BLOCK_READY };

/* Builds block b of row ir unless it is built, or waits while another thread builds it.  A node's
 * values depend only on its place, so the table is the same whoever builds it, in any order. */
static void build_block(const sun_irradiance *t, int ir, int b)
{
    atomic_uchar *state = &t->block_state[(size_t)ir * t->blocks_per_row + b];
    unsigned char expected = BLOCK_EMPTY;
    if (atomic_compare_exchange_strong_explicit(state, &expected, BLOCK_BUILDING, memory_order_acquire,
                                                memory_order_acquire)) {
        int end = (b + 1) * SUN_BLOCK < t->n_mu ? (b + 1) * SUN_BLOCK : t->n_mu;
        for (int imu = b * SUN_BLOCK; imu < end; imu++)
            build_node(t, ir, imu);
        atomic_store_explicit(state, BLOCK_READY, memory_order_release);
        return;
    }
    while (atomic_load_explicit(state, memory_order_acquire) != BLOCK_READY)
        sched_yield();
}

/* Nodes im and im + 1 of row ir, built before they are read. */
static void need_nodes(const sun_irradiance *t, int ir, int im)
{
    const atomic_uchar *row = &t->block_state[(size_t)ir * t->blocks_per_row];
    for (int b = im / SUN_BLOCK; b <= (im + 1) / SUN_BLOCK; b++)
        if (atomic_load_explicit(&row[b], memory_order_acquire) != BLOCK_READY)
            build_block(t, ir, b);
}

/* Whether the air between radii r0 < r1 reaches FM_DENSE_SIGMA_PER_M at every wavelength somewhere
 * (cloud or fog; haze's extinction falls below it in the red):
 * at the ends and at the profiles' nodes between (the profiles are linear between nodes). */
static unsigned char cell_is_dense(const atmosphere *atm, double r0, double r1)
{
    double dz = atm->profile_dz_m > 0.0 ? atm->profile_dz_m : 10.0;
    double sig_s[FM_MAX_WAVELENGTHS], sig_t[FM_MAX_WAVELENGTHS];
    for (double r = r0;; r = fmin(r1, atm->bottom_radius_m + (floor((r - atm->bottom_radius_m) / dz) + 1.0) * dz)) {
        atmosphere_coefficients(atm, r, sig_s, sig_t);
        int dense = 1;
        for (int k = 0; k < atm->grid.count; k++)
            dense &= sig_t[k] >= FM_DENSE_SIGMA_PER_M;
        if (dense)
            return 1;
        if (r >= r1)
            return 0;
    }
}

fm_status sun_irradiance_build(sun_irradiance *table, const atmosphere *atm, const column_table *columns,
                               const sun_disk *sun, int n_r, int n_mu, fm_error *err)
{
    *table = (sun_irradiance){.n_mu = n_mu, .count = atm->grid.count, .atm = atm, .columns = columns, .sun = sun};
    fm_status s = table_rows_init(&table->rows, atm, n_r, err);
    if (s)
        return s;
    int rows = table->rows.count;
    size_t n = (size_t)rows * (size_t)n_mu * (size_t)table->count;
    table->blocks_per_row = (n_mu + SUN_BLOCK - 1) / SUN_BLOCK;
    table->normal = malloc(n * sizeof(float));
    table->horizontal = malloc((size_t)n_mu * (size_t)table->count * sizeof(float));
    table->few = malloc((size_t)rows * (size_t)n_mu * SUN_FEW * sizeof(float));
    table->few_count = sun_irradiance_few_wavelengths(table->count, table->few_k);
    table->mu_lo = malloc((size_t)rows * sizeof(double));
    table->per_mu_span = malloc((size_t)rows * sizeof(double));
    table->block_state = calloc((size_t)rows * (size_t)table->blocks_per_row, sizeof(atomic_uchar));
    table->dense_cell = malloc((size_t)rows);
    if (!table->normal || !table->horizontal || !table->few || !table->mu_lo || !table->per_mu_span ||
        !table->block_state || !table->dense_cell) {
        sun_irradiance_free(table);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the sun irradiance table");
    }
    for (int i = 0; i < rows; i++) {
        table->mu_lo[i] = mu_low(atm, sun, table_rows_radius(&table->rows, atm, i));
        table->per_mu_span[i] = 1.0 / (1.0 - table->mu_lo[i]);
    }
    for (int i = 0; i + 1 < rows; i++)
        table->dense_cell[i] = cell_is_dense(atm, table_rows_radius(&table->rows, atm, i),
                                             table_rows_radius(&table->rows, atm, i + 1));
    table->dense_cell[rows - 1] = 0;
    return FM_OK;
}

void sun_irradiance_free(sun_irradiance *table)
{
    free(table->normal);
    free(table->horizontal);
    free(table->few);
    free(table->mu_lo);
    free(table->per_mu_span);
    free((void *)table->block_state);
    free(table->dense_cell);
    table->dense_cell = NULL;
    table->normal = table->horizontal = table->few = NULL;
    table->mu_lo = table->per_mu_span = NULL;
    table->block_state = NULL;
    table_rows_free(&table->rows);
}

sun_row_place sun_irradiance_row_place(const sun_irradiance *table, const atmosphere *atm, double r)
{
    sun_row_place place;
    place.row = table_rows_locate(&table->rows, atm, r, &place.t);
    return place;
}

/* Bilinear weights and node offsets of mu_s at a radius between rows ir and ir + 1 (tr of the way);
 * returns 1 when the point is fully in the Earth's shadow for either row (then the weights are
 * unused). */
static int locate_at(const sun_irradiance *table, int ir, double tr, double mu_s, double w[4], size_t idx[4])
{
    const int K = table->count;
    /* the mu mapping depends on the row's radius: locate mu_s in each of the two rows, both rows'
     * quotients (within 2 ulp, by the row's reciprocal) and then both square roots, so that the two
     * rows' chains overlap (0 below mu_lo) */
    const double *mu_lo = table->mu_lo + ir, *per_span = table->per_mu_span + ir;
    double q[2], xs[2];
    for (int row = 0; row < 2; row++)
        q[row] = mu_s <= mu_lo[row] ? 0.0 : (mu_s - mu_lo[row]) * per_span[row];
    for (int row = 0; row < 2; row++)
        xs[row] = sqrt(q[row]);
    int dark = 0;
    for (int row = 0; row < 2; row++) {
        double lo = mu_lo[row], x = xs[row];
        double fm = clamp_between(x, 0.0, 1.0) * (table->n_mu - 1);
        int im = (int)fm;
        if (im > table->n_mu - 2)
            im = table->n_mu - 2;
        double tm = mu_s <= lo ? -1.0 : fm - im; /* below the lowest node: fully set */
        if (tm < 0.0)
            dark = 1;
        double wr = row == 0 ? 1.0 - tr : tr;
        if (!dark)
            need_nodes(table, ir + row, im);
        idx[2 * row] = ((size_t)(ir + row) * table->n_mu + im) * K;
        idx[2 * row + 1] = idx[2 * row] + K;
        if (tm < 0.0) {
            w[2 * row] = w[2 * row + 1] = 0.0;
        } else {
            w[2 * row] = wr * (1.0 - tm);
            w[2 * row + 1] = wr * tm;
        }
    }
    return dark;
}

/* locate_at the rows about radius r. */
static int locate(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun, double r, double mu_s,
                  double w[4], size_t idx[4])
{
    double tr;
    int ir = table_rows_locate(&table->rows, atm, r, &tr);
    return locate_at(table, ir, tr, mu_s, w, idx);
}

/* A depth as lookups return it: infinite (Tbar 0) at MAX_DEPTH and beyond. */
static double depth_or_dark(double d) { return d < MAX_DEPTH ? d : INFINITY; }

static double interpolate_depth(const float *v, const double w[4], const size_t idx[4], int k)
{
    return w[0] * v[idx[0] + k] + w[1] * v[idx[1] + k] + w[2] * v[idx[2] + k] + w[3] * v[idx[3] + k];
}

/* interpolate_depth of every wavelength, the corners' rows read as separate streams so that the
 * loop runs in vector lanes (one row's K values lie side by side) */
static void interpolate_depths(const float *v, const double w[4], const size_t idx[4], int K, double *restrict d)
{
    const float *restrict c0 = v + idx[0], *restrict c1 = v + idx[1];
    const float *restrict c2 = v + idx[2], *restrict c3 = v + idx[3];
    for (int k = 0; k < K; k++)
        d[k] = w[0] * c0[k] + w[1] * c1[k] + w[2] * c2[k] + w[3] * c3[k];
}

/* exp(-depth) of every wavelength's interpolated depth, 0 beyond MAX_DEPTH, the exps in vector lanes
 * (exp_array.h) */
static void exp_of_depths(const float *v, const double w[4], const size_t idx[4], int K, double *out)
{
    interpolate_depths(v, w, idx, K, out);
    for (int k = 0; k < K; k++)
        out[k] = -depth_or_dark(out[k]);
    exp_array(out, out, K);
}

/* Across a cell whose rows' depths differ by more than this (inside a cloud), the depth is not
 * linear between the rows (it bends at the cloud's edges and with the radius mapping): there
 * depths_through_thick_cell takes the column to the row above exactly.  Clear air's cells differ by
 * < 0.02 by day and keep the bilinear lookup. */
#define THICK_CELL_DEPTH 0.05
/* Deeper in than this at the row above (sunlight below e^-50), the bilinear depth is as good as any:
 * the light is nil either way, and most vertices deep in a thick cloud skip the exact piece. */
#define DIM_DEPTH 50.0
/* Outside cloud and fog, only with the sun more than 5.7 degrees above the local horizontal: lower,
 * clear air's cells differ by more than THICK_CELL_DEPTH (at twilight every vertex's), and the
 * bilinear lookup stays there.  In a cell of cloud or fog (dense_cell) the exact piece is taken at
 * every sun: the beam's depth bends most at a low sun (at a cosine of 0.05 it falls by e in 2 m of
 * a deck's top), and the lookups there are a cloud's vertices only
 * (docs/decisions/2026-12-07-thick-cell-low-sun.md). */
#define THICK_CELL_MIN_MU 0.1

/* Whether the cell whose corners are (w, idx) takes the thick-cell test at mu_s: weights on both
 * rows, and the sun high enough or the cell dense (THICK_CELL_MIN_MU). */
static int thick_test_applies(const sun_irradiance *table, double mu_s, const double w[4], const size_t idx[4])
{
    if (!(w[0] + w[1] > 0.0 && w[2] + w[3] > 0.0))
        return 0;
    size_t row_up = idx[2] / ((size_t)table->n_mu * (size_t)table->count);
    return mu_s > THICK_CELL_MIN_MU || table->dense_cell[row_up - 1];
}

/* interpolate_depths, and in the same pass over the corners whether the cell is thick (its rows'
 * depths differ by more than THICK_CELL_DEPTH at some wavelength) and lit at the row above (some
 * depth below DIM_DEPTH).  Each row's depth is its corners' weighted sum over their weights; the
 * lower row's sum is the first part of the bilinear one, as interpolate_depths adds them. */
static void interpolate_and_test(const float *v, const double w[4], const size_t idx[4], int K, double *restrict d,
                                 int *thick_out, int *lit_out)
{
    const float *restrict c0 = v + idx[0], *restrict c1 = v + idx[1];
    const float *restrict c2 = v + idx[2], *restrict c3 = v + idx[3];
    const double w_lo = w[0] + w[1], w_hi = w[2] + w[3];
    int thick = 0, lit = 0;
    for (int k = 0; k < K; k++) {
        double lo_sum = w[0] * c0[k] + w[1] * c1[k], hi_2 = w[2] * c2[k], hi_3 = w[3] * c3[k];
        d[k] = lo_sum + hi_2 + hi_3;
        double lo = lo_sum / w_lo, hi = (hi_2 + hi_3) / w_hi;
        thick |= fabs(lo - hi) > THICK_CELL_DEPTH;
        lit |= hi < DIM_DEPTH;
    }
    *thick_out = thick;
    *lit_out = lit;
}

/* At (r, mu_s) in a thick cell whose upper row is row_up: the depth as the exact column along the
 * sun's central direction up to that row plus the row's depth where the ray meets it (the disk's
 * spread over so short a piece is negligible with the sun above about 2 degrees or the sunlight
 * above a few percent); returns 0 (nothing written) where the row above is dark or not met. */
static int depths_through_thick_cell(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                     double r, double mu_s, int row_up, double *depth)
{
    double r_up = table_rows_radius(&table->rows, atm, row_up);
    if (!(r_up > r) || ray_hits_ground(atm, r, mu_s))
        return 0;
    double t = -r * mu_s + sqrt(fmax(0.0, r * r * (mu_s * mu_s - 1.0) + r_up * r_up));
    double mu_up = clamp_cosine((r * mu_s + t) / r_up), w_up[4], col[FM_MAX_SPECIES], piece[FM_MAX_WAVELENGTHS];
    size_t idx_up[4];
    if (locate(table, atm, sun, r_up, mu_up, w_up, idx_up))
        return 0;
    interpolate_depths(table->normal, w_up, idx_up, table->count, depth);
    column_exact(atm, r, mu_s, t, col);
    atmosphere_optical_depths(atm, col, piece);
    for (int k = 0; k < table->count; k++)
        depth[k] += piece[k];
    return 1;
}

/* The depths at (r, mu_s) in the lit cell whose corners are (w, idx): bilinear, or through a thick
 * cell exactly (depths_through_thick_cell). */
static void cell_depths(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun, double r,
                        double mu_s, const double w[4], const size_t idx[4], double *depth)
{
    const int K = table->count;
    if (!thick_test_applies(table, mu_s, w, idx)) {
        interpolate_depths(table->normal, w, idx, K, depth);
        return;
    }
    int thick, lit;
    interpolate_and_test(table->normal, w, idx, K, depth, &thick, &lit);
    if (thick && lit)
        depths_through_thick_cell(table, atm, sun, r, mu_s, (int)(idx[2] / ((size_t)table->n_mu * (size_t)K)), depth);
}

void sun_irradiance_lookup(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun, double r,
                           double mu_s, double *normal)
{
    sun_cell cell;
    sun_irradiance_cell(table, atm, r, mu_s, &cell);
    sun_irradiance_cell_transmittances(table, atm, sun, &cell, r, mu_s, normal);
}

void sun_irradiance_cell_transmittances(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                        const sun_cell *cell, double r, double mu_s, double *normal)
{
    const int K = table->count;
    if (cell->dark) {
        spectral_fill(normal, 0.0, K);
        return;
    }
    cell_depths(table, atm, sun, r, mu_s, cell->w, cell->idx, normal);
    for (int k = 0; k < K; k++)
        normal[k] = -depth_or_dark(normal[k]);
    exp_array(normal, normal, K);
}

void sun_irradiance_lookup_ground(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                  double mu_s, double *normal, double *horizontal)
{
    const int K = table->count;
    double w[4];
    size_t idx[4];
    if (locate(table, atm, sun, atm->bottom_radius_m, mu_s, w, idx)) {
        for (int k = 0; k < K; k++)
            normal[k] = horizontal[k] = 0.0;
        return;
    }
    exp_of_depths(table->normal, w, idx, K, normal);
    /* the ground is the first row (weights w[2], w[3] are 0 there), the horizontal table's only one */
    double ground_w[4] = {w[0], w[1], 0.0, 0.0};
    size_t ground_idx[4] = {idx[0], idx[1], idx[0], idx[1]};
    exp_of_depths(table->horizontal, ground_w, ground_idx, K, horizontal);
}

int sun_irradiance_lookup_depth(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun, double r,
                                double mu_s, double *depth)
{
    return sun_irradiance_lookup_depth_at(table, atm, sun, sun_irradiance_row_place(table, atm, r), r, mu_s, depth);
}

int sun_irradiance_lookup_depth_at(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                   sun_row_place place, double r, double mu_s, double *depth)
{
    sun_cell cell;
    sun_irradiance_cell_at(table, place, mu_s, &cell);
    return sun_irradiance_cell_depths(table, atm, sun, &cell, r, mu_s, depth);
}

/* The cache lines of a node's K floats. */
static void prefetch_node(const float *node, int K)
{
    for (int k = 0; k < K; k += 16)
        __builtin_prefetch(node + k);
    __builtin_prefetch(node + K - 1);
}

void sun_irradiance_cell_at(const sun_irradiance *table, sun_row_place place, double mu_s, sun_cell *cell)
{
    cell->dark = locate_at(table, place.row, place.t, mu_s, cell->w, cell->idx);
    if (cell->dark)
        return;
    for (int c = 0; c < 4; c += 2) /* a row's two nodes lie side by side */
        prefetch_node(table->normal + cell->idx[c], 2 * table->count);
}

void sun_irradiance_cell(const sun_irradiance *table, const atmosphere *atm, double r, double mu_s, sun_cell *cell)
{
    sun_irradiance_cell_at(table, sun_irradiance_row_place(table, atm, r), mu_s, cell);
}

int sun_irradiance_cell_depths(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                               const sun_cell *cell, double r, double mu_s, double *depth)
{
    const int K = table->count;
    if (cell->dark) {
        spectral_fill(depth, INFINITY, K);
        return 0;
    }
    cell_depths(table, atm, sun, r, mu_s, cell->w, cell->idx, depth);
    for (int k = 0; k < K; k++)
        depth[k] = depth_or_dark(depth[k]);
    return 1;
}

int sun_irradiance_lookup_some_depths(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                      double r, double mu_s, int n, const int *ks, double *depth)
{
    double w[4];
    size_t idx[4];
    int dark = locate(table, atm, sun, r, mu_s, w, idx);
    for (int i = 0; i < n; i++)
        depth[i] = dark ? INFINITY : depth_or_dark(interpolate_depth(table->normal, w, idx, ks[i]));
    return !dark;
}

int sun_irradiance_lookup_few_depths(const sun_irradiance *table, const atmosphere *atm, const sun_disk *sun,
                                     double r, double mu_s, double *depth)
{
    sun_cell cell;
    sun_irradiance_few_cell(table, atm, r, mu_s, &cell);
    return sun_irradiance_few_cell_depths(table, &cell, depth);
}

void sun_irradiance_few_cell(const sun_irradiance *table, const atmosphere *atm, double r, double mu_s, sun_cell *cell)
{
    double tr;
    int ir = table_rows_locate(&table->rows, atm, r, &tr);
    cell->dark = locate_at(table, ir, tr, mu_s, cell->w, cell->idx);
    for (int c = 0; c < 4; c++) /* the corners' nodes in the compact copy */
        cell->idx[c] = cell->idx[c] / (size_t)table->count * SUN_FEW;
    if (cell->dark)
        return;
    for (int c = 0; c < 4; c += 2) { /* a row's two nodes lie side by side */
        __builtin_prefetch(table->few + cell->idx[c]);
        __builtin_prefetch(table->few + cell->idx[c] + 2 * SUN_FEW - 1);
    }
}

int sun_irradiance_few_cell_depths(const sun_irradiance *table, const sun_cell *cell, double *depth)
{
    for (int j = 0; j < table->few_count; j++)
        depth[j] = cell->dark ? INFINITY : depth_or_dark(interpolate_depth(table->few, cell->w, cell->idx, j));
    return !cell->dark;
}

int sun_in_umbra(const atmosphere *atm, const sun_disk *sun, double r, double mu_s)
{
    return mu_s <= mu_low(atm, sun, r);
}

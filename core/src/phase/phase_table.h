/* Tabulated phase functions (phase_table): building a table from values at angles theta_j,
 * evaluating it (linear in cos_theta between nodes), sampling it by exact inversion of its
 * cumulative distribution, and its exact asymmetry parameter.
 * Per wavelength k the function is p_k(mu) = v_kj + (v_k,j+1 - v_kj) (mu_j - mu) / (mu_j - mu_j+1)
 * on [mu_j+1, mu_j]; the stored values are scaled so that 2 pi times the trapezoid sum in mu (the
 * exact integral of that function over the sphere) is 1. */
#ifndef FM_PHASE_PHASE_TABLE_H
#define FM_PHASE_PHASE_TABLE_H

#include "firmament/firmament.h"

/* A phase function tabulated at angles theta_j (ascending from 0 to pi) for every grid wavelength,
 * linear in cos_theta between nodes and normalised so that the piecewise-linear function integrates
 * to exactly 1; sampling inverts its cumulative distribution exactly (bin by the table, then the
 * linear density inside the bin). */
typedef struct phase_table {
    int wavelength_count; /* K */
    int angle_count;      /* n >= 2 */
    double *mu;           /* [n] cos(theta_j), descending from 1 to -1 */
    double *value;        /* [n][K] sr^-1: a node's values for all wavelengths side by side, which
                           * evaluating every wavelength at one angle reads (phase_table_eval_all) */
    double *cdf;          /* [K][n] probability of cos_theta >= mu_j */
    int *first_bin;       /* [2n - 1]: the bin at the start of each of 2n - 2 equal steps of
                           * u = (sin(theta / 2))^(1/2) (phase_table_bin) */
    int *sample_bin;      /* [K][n]: per wavelength, the bin that phase_table_sample's u of each of
                           * n - 1 equal steps starts its search from */
} phase_table;

/* Builds *out from values[k * angle_count + j] at theta_rad[j]; checks the inputs as
 * phase_init_tabulated documents.  *out is set only on success. */
fm_status phase_table_create(phase_table **out, int wavelength_count, int angle_count, const double *theta_rad,
                             const double *values, fm_error *err);
void phase_table_destroy(phase_table *t);

/* Index j of the bin [mu_j+1, mu_j] holding cos_theta (clamped to [-1, 1]), in 0 .. n-2. */
int phase_table_bin(const phase_table *t, double cos_theta);

/* Values (sr^-1) at cos_theta: for wavelength k, and for wavelengths 0 .. K-1 (K at most the
 * table's wavelength_count) with one bin search. */
double phase_table_eval(const phase_table *t, int k, double cos_theta);
void phase_table_eval_all(const phase_table *t, int K, double cos_theta, double *out);

/* cos_theta drawn with density phase_table_eval at wavelength k, from u uniform in [0, 1)
 * (u = 0 gives the forward direction, cos_theta = 1). */
double phase_table_sample(const phase_table *t, int k, double u);

/* Mean cos_theta at wavelength k, exact for the piecewise-linear function. */
double phase_table_asymmetry(const phase_table *t, int k);

#endif

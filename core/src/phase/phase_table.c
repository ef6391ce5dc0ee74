#include "phase/phase_table.h"

#include "base/status.h"
#include "base/units.h"
#include "base/vec.h"
#include "spectrum/spectral_grid.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

/* Angles this close to 0 and pi count as the ends of the grid (tables converted from degrees). */
#define PHASE_TABLE_END_TOLERANCE_RAD 1e-9

static fm_status bad_table(fm_error *err, const char *fmt, ...) FM_PRINTF(2, 3);

/* One line "phase table: ..." with FM_ERR_INVALID_ARGUMENT. */
static fm_status bad_table(fm_error *err, const char *fmt, ...)
{
    char what[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "phase table: %s", what);
}

static fm_status check_inputs(int K, int n, const double *theta_rad, const double *values, fm_error *err)
{
    if (K < 1 || K > FM_MAX_WAVELENGTHS)
        return bad_table(err, "%d wavelengths is outside [1, %d]", K, FM_MAX_WAVELENGTHS);
    if (n < 2)
        return bad_table(err, "%d angles (at least 2 are needed)", n);
    if (!theta_rad || !values)
        return bad_table(err, "no angles or no values given");
    for (int j = 0; j < n; j++)
        if (!isfinite(theta_rad[j]))
            return bad_table(err, "angle %d is not finite", j);
    const double tol = PHASE_TABLE_END_TOLERANCE_RAD;
    if (fabs(theta_rad[0]) > tol || fabs(theta_rad[n - 1] - FM_PI) > tol)
        return bad_table(err, "angles run from %g to %g rad, not from 0 to pi", theta_rad[0], theta_rad[n - 1]);
    for (int j = 0; j + 1 < n; j++)
        if (!(theta_rad[j + 1] > theta_rad[j]))
            return bad_table(err, "angle %d (%g rad) does not exceed angle %d (%g rad)", j + 1, theta_rad[j + 1], j,
                             theta_rad[j]);
    for (int k = 0; k < K; k++)
        for (int j = 0; j < n; j++) {
            double v = values[(size_t)k * n + j];
            if (!isfinite(v) || v < 0.0)
                return bad_table(err, "value %g at wavelength %d, angle %d is not finite and >= 0", v, k, j);
        }
    return FM_OK;
}

static int searched_bin(const phase_table *t, double cos_theta)
{
    /* largest j <= n-2 with mu_j >= cos_theta (mu descending, mu_0 = 1) */
    int lo = 0, hi = t->angle_count - 1;
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (t->mu[mid] >= cos_theta)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static void sample_bins(phase_table *t, int k);

fm_status phase_table_create(phase_table **out, int K, int n, const double *theta_rad, const double *values,
                             fm_error *err)
{
    fm_status st = check_inputs(K, n, theta_rad, values, err);
    if (st != FM_OK)
        return st;

    phase_table *t = calloc(1, sizeof *t);
    if (!t)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for a phase table");
    t->wavelength_count = K;
    t->angle_count = n;
    t->mu = malloc((size_t)n * sizeof *t->mu);
    t->value = malloc((size_t)K * n * sizeof *t->value);
    t->cdf = malloc((size_t)K * n * sizeof *t->cdf);
    t->first_bin = malloc((size_t)(2 * n - 1) * sizeof *t->first_bin);
    t->sample_bin = malloc((size_t)K * n * sizeof *t->sample_bin);
    if (!t->mu || !t->value || !t->cdf || !t->first_bin || !t->sample_bin) {
        phase_table_destroy(t);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for a phase table");
    }

    /* The ends are exact so that every cos_theta in [-1, 1] falls in a bin. */
    t->mu[0] = 1.0;
    t->mu[n - 1] = -1.0;
    for (int j = 1; j + 1 < n; j++)
        t->mu[j] = cos(theta_rad[j]);
    for (int j = 0; j + 1 < n; j++)
        if (!(t->mu[j + 1] < t->mu[j])) {
            phase_table_destroy(t);
            return bad_table(err, "angles %d and %d (%.17g rad) have the same cosine", j, j + 1, theta_rad[j + 1]);
        }

    for (int k = 0; k < K; k++) {
        const double *v = values + (size_t)k * n;
        double *cdf = t->cdf + (size_t)k * n;
        /* integral over the sphere of the piecewise-linear function: 2 pi * trapezoid sum in mu */
        double total = 0.0;
        for (int j = 0; j + 1 < n; j++)
            total += FM_PI * (v[j] + v[j + 1]) * (t->mu[j] - t->mu[j + 1]);
        if (!(total > 0.0) || !isfinite(total)) {
            phase_table_destroy(t);
            return bad_table(err, "wavelength %d integrates to %g over the sphere", k, total);
        }
        for (int j = 0; j < n; j++)
            t->value[(size_t)j * K + k] = v[j] / total;
        cdf[0] = 0.0;
        for (int j = 0; j + 1 < n; j++)
            cdf[j + 1] = cdf[j] + FM_PI * (t->value[(size_t)j * K + k] + t->value[(size_t)(j + 1) * K + k]) *
                                      (t->mu[j] - t->mu[j + 1]);
        /* Dividing by the sum makes the last entry, and a trailing zero plateau, exactly 1, so that a
         * u < 1 never selects an empty bin. */
        double sum = cdf[n - 1];
        for (int j = 1; j < n; j++)
            cdf[j] /= sum;
    }
    for (int k = 0; k < K; k++)
        sample_bins(t, k);
    for (int m = 0, steps = 2 * n - 2; m <= steps; m++) {
        double u = (double)m / steps;
        t->first_bin[m] = searched_bin(t, 1.0 - 2.0 * u * u * u * u);
    }
    *out = t;
    return FM_OK;
}

/* For wavelength k, sample_bin[m] = the largest j <= n-2 with cdf_j <= m / (n - 1). */
static void sample_bins(phase_table *t, int k)
{
    const int n = t->angle_count;
    const double *cdf = t->cdf + (size_t)k * n;
    int *bin = t->sample_bin + (size_t)k * n;
    for (int m = 0, j = 0; m < n; m++) {
        double u = (double)m / (n - 1);
        while (j < n - 2 && cdf[j + 1] <= u)
            j++;
        bin[m] = j;
    }
}

void phase_table_destroy(phase_table *t)
{
    if (!t)
        return;
    free(t->mu);
    free(t->value);
    free(t->cdf);
    free(t->first_bin);
    free(t->sample_bin);
    free(t);
}

/* The bin from the step of u that cos_theta falls in, moved to the exact one: the same bin as the
 * binary search (also for cos_theta beyond [-1, 1] or NaN: bin 0), in one or two comparisons instead
 * of nine for the 301 angles of the aerosol tables (every vertex evaluates each species' table). */
int phase_table_bin(const phase_table *t, double cos_theta)
{
    const int n = t->angle_count, steps = 2 * n - 2;
    /* u = (sin(theta / 2))^(1/2) = ((1 - cos_theta) / 2)^(1/4) runs from 0 (forward) to 1 (backward)
     * and is nearly linear in the index of aerosol grids (theta_j ~ j^2, aerosol_optics.h); in floats:
     * it only starts the search, which the loops below move to the exact bin from any start */
    float u = sqrtf(sqrtf((float)(0.5 * (1.0 - clamp_cosine(cos_theta)))));
    int j = t->first_bin[u > 0.0 ? (u < 1.0 ? (int)(u * steps) : steps) : 0];
    while (j > 0 && !(t->mu[j] >= cos_theta))
        j--;
    while (j < n - 2 && t->mu[j + 1] >= cos_theta)
        j++;
    return j;
}

/* Fraction of the way from node j to node j+1 at which cos_theta lies. */
static inline double bin_weight(const phase_table *t, int j, double cos_theta)
{
    double w = (t->mu[j] - cos_theta) / (t->mu[j] - t->mu[j + 1]);
    return w < 0.0 ? 0.0 : (w > 1.0 ? 1.0 : w);
}

static inline double lerp_value(const phase_table *t, int k, int j, double w)
{
    const double *v0 = t->value + (size_t)j * t->wavelength_count + k, *v1 = v0 + t->wavelength_count;
    return *v0 + w * (*v1 - *v0);
}

double phase_table_eval(const phase_table *t, int k, double cos_theta)
{
    int j = phase_table_bin(t, cos_theta);
    return lerp_value(t, k, j, bin_weight(t, j, cos_theta));
}

void phase_table_eval_all(const phase_table *t, int K, double cos_theta, double *out)
{
    int j = phase_table_bin(t, cos_theta);
    double w = bin_weight(t, j, cos_theta);
    const double *v0 = t->value + (size_t)j * t->wavelength_count, *v1 = v0 + t->wavelength_count;
    for (int k = 0; k < K; k++)
        out[k] = v0[k] + w * (v1[k] - v0[k]);
}

double phase_table_sample(const phase_table *t, int k, double u)
{
    const int n = t->angle_count;
    const double *cdf = t->cdf + (size_t)k * n;
    /* bin: largest j <= n-2 with cdf_j <= u (cdf ascending from 0), which skips empty bins; from the
     * bin of u's step, which is at most that (a droplet table's forward peak made a binary search
     * over its angles the slowest part of a walk through a deck) */
    double step = u * (n - 1);
    int j = t->sample_bin[(size_t)k * n + (step > 0.0 ? (step < n - 1 ? (int)step : n - 1) : 0)];
    while (j < n - 2 && cdf[j + 1] <= u)
        j++;
    const double v0 = t->value[(size_t)j * t->wavelength_count + k], v1 = t->value[(size_t)(j + 1) * t->wavelength_count + k];
    const double width = t->mu[j] - t->mu[j + 1];
    /* Inside the bin, with x = mu_j - cos_theta in [0, width], the probability of [0, x] is
     * a x^2 + b x, a = pi (v_j+1 - v_j) / width, b = 2 pi v_j.  The root of a x^2 + b x = r written as
     * 2 r / (b + sqrt(b^2 + 4 a r)) has no cancellation: it tends to r / b as the slope vanishes and
     * to sqrt(r / a) where the density starts from zero. */
    double r = u - cdf[j];
    double a = FM_PI * (v1 - v0) / width, b = 2.0 * FM_PI * v0;
    double disc = b * b + 4.0 * a * r;
    double den = b + sqrt(disc > 0.0 ? disc : 0.0);
    double x = (r > 0.0 && den > 0.0) ? 2.0 * r / den : 0.0;
    if (x > width)
        x = width;
    return t->mu[j] - x;
}

double phase_table_asymmetry(const phase_table *t, int k)
{
    /* 2 pi times the integral of mu p(mu): over a bin [m1, m0] with p linear from p1 to p0 it is
     * (m0 - m1) / 6 * (p1 (2 m1 + m0) + p0 (m1 + 2 m0)), exact for a linear p. */
    const int n = t->angle_count;
    const int K = t->wavelength_count;
    const double *v = t->value + k, *mu = t->mu; /* v[j * K]: node j */
    double g = 0.0;
    for (int j = 0; j + 1 < n; j++)
        g += (mu[j] - mu[j + 1]) / 6.0 *
             (v[(size_t)(j + 1) * K] * (2.0 * mu[j + 1] + mu[j]) + v[(size_t)j * K] * (mu[j + 1] + 2.0 * mu[j]));
    return 2.0 * FM_PI * g;
}

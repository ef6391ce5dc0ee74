/* A spectral vector: one value per wavelength of the spectral grid (spectral_grid.h), of which the
 * first K (the grid's count) are used, and the per-wavelength operations of the estimators.
 *
 * Each operation is the loop over k < K of the scalar expression in its comment, evaluated left to
 * right as written (ISO C: the compiler fuses no multiply-adds), so a loop replaced by one gives the
 * same numbers bit for bit.  Arguments are arrays of at least K values; a spectral decays to one. */
#ifndef FM_SPECTRUM_SPECTRAL_H
#define FM_SPECTRUM_SPECTRAL_H

#include "spectrum/spectral_grid.h"

typedef double spectral[FM_MAX_WAVELENGTHS];

/* a[k] = x */
static inline void spectral_fill(double *a, double x, int K)
{
    for (int k = 0; k < K; k++)
        a[k] = x;
}

/* a[k] = b[k] */
static inline void spectral_copy(double *a, const double *b, int K)
{
    for (int k = 0; k < K; k++)
        a[k] = b[k];
}

/* a[k] += b[k] */
static inline void spectral_add(double *a, const double *b, int K)
{
    for (int k = 0; k < K; k++)
        a[k] += b[k];
}

/* a[k] += x * b[k] */
static inline void spectral_add_scaled(double *a, double x, const double *b, int K)
{
    for (int k = 0; k < K; k++)
        a[k] += x * b[k];
}

/* a[k] *= b[k] */
static inline void spectral_mul(double *a, const double *b, int K)
{
    for (int k = 0; k < K; k++)
        a[k] *= b[k];
}

/* a[k] *= x */
static inline void spectral_scale(double *a, double x, int K)
{
    for (int k = 0; k < K; k++)
        a[k] *= x;
}

/* a[k] /= x */
static inline void spectral_divide(double *a, double x, int K)
{
    for (int k = 0; k < K; k++)
        a[k] /= x;
}

/* a[k] = -b[k] */
static inline void spectral_negate(double *a, const double *b, int K)
{
    for (int k = 0; k < K; k++)
        a[k] = -b[k];
}

/* a[k] += x - b[k]: an optical depth relative to one wavelength's, summed */
static inline void spectral_add_difference(double *a, double x, const double *b, int K)
{
    for (int k = 0; k < K; k++)
        a[k] += x - b[k];
}

/* a[k] *= b[k] / x: a ratio to one wavelength's value, or a weight over a pdf */
static inline void spectral_mul_ratio(double *a, const double *b, double x, int K)
{
    for (int k = 0; k < K; k++)
        a[k] *= b[k] / x;
}

/* a[k] = x * b[k] * c[k]: a path's throughput scaled (the first factors of a contribution) */
static inline void spectral_product(double *a, double x, const double *b, const double *c, int K)
{
    for (int k = 0; k < K; k++)
        a[k] = x * b[k] * c[k];
}

/* a[k] += x * b[k] * c[k] * d[k]: a path's contribution, x b c its throughput (one pass) */
static inline void spectral_add_product(double *a, double x, const double *b, const double *c, const double *d, int K)
{
    for (int k = 0; k < K; k++)
        a[k] += x * b[k] * c[k] * d[k];
}

/* a[k] += x * b[k] * c[k] * d[k] * e[k] * f[k] (one pass) */
static inline void spectral_add_product5(double *a, double x, const double *b, const double *c, const double *d,
                                         const double *e, const double *f, int K)
{
    for (int k = 0; k < K; k++)
        a[k] += x * b[k] * c[k] * d[k] * e[k] * f[k];
}

/* sum of a[k], from 0 in order of k */
static inline double spectral_sum(const double *a, int K)
{
    double s = 0.0;
    for (int k = 0; k < K; k++)
        s += a[k];
    return s;
}

/* sum of a[k] b[k], from 0 in order of k */
static inline double spectral_dot(const double *a, const double *b, int K)
{
    double s = 0.0;
    for (int k = 0; k < K; k++)
        s += a[k] * b[k];
    return s;
}

/* sum of a[k] / K */
static inline double spectral_mean(const double *a, int K) { return spectral_sum(a, K) / K; }

/* the largest of 0 and a[k] */
static inline double spectral_max(const double *a, int K)
{
    double m = 0.0;
    for (int k = 0; k < K; k++)
        m = m > a[k] ? m : a[k];
    return m;
}

/* the largest of 0 and a[k] b[k] */
static inline double spectral_max_product(const double *a, const double *b, int K)
{
    double m = 0.0;
    for (int k = 0; k < K; k++) {
        double x = a[k] * b[k];
        m = m > x ? m : x;
    }
    return m;
}

#endif

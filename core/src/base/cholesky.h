/* Cholesky factorisation and solution of small dense symmetric positive definite systems, the
 * matrix row-major with `stride` doubles per row (only its lower triangle is read and written). */
#ifndef FM_BASE_CHOLESKY_H
#define FM_BASE_CHOLESKY_H

#include <math.h>

/* In-place Cholesky factor L (lower triangle, A = L L^T) of the n x n matrix a; 0 if A is not
 * positive definite. */
static inline int cholesky(int n, int stride, double *a)
{
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++) {
            double sum = a[i * stride + j];
            for (int k = 0; k < j; k++)
                sum -= a[i * stride + k] * a[j * stride + k];
            if (i == j) {
                if (!(sum > 0.0))
                    return 0;
                a[i * stride + i] = sqrt(sum);
            } else {
                a[i * stride + j] = sum / a[j * stride + j];
            }
        }
    return 1;
}

/* x = (L L^T)^-1 b for the factor L of cholesky (x may not alias b). */
static inline void cholesky_solve(int n, int stride, const double *L, const double *b, double *x)
{
    for (int i = 0; i < n; i++) {
        double sum = b[i];
        for (int k = 0; k < i; k++)
            sum -= L[i * stride + k] * x[k];
        x[i] = sum / L[i * stride + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double sum = x[i];
        for (int k = i + 1; k < n; k++)
            sum -= L[k * stride + i] * x[k];
        x[i] = sum / L[i * stride + i];
    }
}

#endif

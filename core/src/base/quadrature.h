/* Gauss-Legendre quadrature nodes and weights on [-1, 1] (computed by Newton iteration on the
 * Legendre recurrence; exact for polynomials of degree 2n - 1). */
#ifndef FM_BASE_QUADRATURE_H
#define FM_BASE_QUADRATURE_H

#define FM_GAUSS_MAX 64

typedef struct gauss_rule {
    int n;
    double x[FM_GAUSS_MAX], w[FM_GAUSS_MAX];
} gauss_rule;

/* Fills rule with n in [1, FM_GAUSS_MAX] points, nodes increasing. */
void gauss_legendre(int n, gauss_rule *rule);

/* The same rule from a table computed once for every n (thread-safe, never NULL). */
const gauss_rule *gauss_legendre_cached(int n);

#endif

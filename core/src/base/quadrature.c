#include "base/quadrature.h"

#include "base/units.h"

#include <math.h>
#include <pthread.h>

void gauss_legendre(int n, gauss_rule *rule)
{
    if (n < 1)
        n = 1;
    if (n > FM_GAUSS_MAX)
        n = FM_GAUSS_MAX;
    rule->n = n;
    for (int i = 0; i < (n + 1) / 2; i++) {
        /* Tricomi's initial guess, then Newton on P_n. */
        double x = cos(FM_PI * (i + 0.75) / (n + 0.5));
        double dp = 1.0;
        for (int iter = 0; iter < 100; iter++) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= n; k++) {
                double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (x * p1 - p0) / (x * x - 1.0);
            double dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16)
                break;
        }
        double w = 2.0 / ((1.0 - x * x) * dp * dp);
        rule->x[i] = -x;
        rule->w[i] = w;
        rule->x[n - 1 - i] = x;
        rule->w[n - 1 - i] = w;
    }
    if (n % 2 == 1) {
        rule->x[n / 2] = 0.0; /* exact centre */
    }
}

static gauss_rule cached_rules[FM_GAUSS_MAX + 1];
static pthread_once_t cached_once = PTHREAD_ONCE_INIT;

static void fill_cached_rules(void)
{
    for (int n = 1; n <= FM_GAUSS_MAX; n++)
        gauss_legendre(n, &cached_rules[n]);
}

const gauss_rule *gauss_legendre_cached(int n)
{
    pthread_once(&cached_once, fill_cached_rules);
    if (n < 1)
        n = 1;
    if (n > FM_GAUSS_MAX)
        n = FM_GAUSS_MAX;
    return &cached_rules[n];
}

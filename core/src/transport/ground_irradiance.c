#include "transport/ground_irradiance.h"

#include "base/units.h"
#include "spectrum/spectral.h"

#include <math.h>
#include <stdlib.h>

#define NODE_SPACING (0.5 * FM_DEG) /* of the local sun zenith angle, at most */

int ground_irradiance_angle_count(double theta_s, double max_offset)
{
    double lo = fmax(0.0, theta_s - max_offset), hi = fmin(FM_PI, theta_s + max_offset);
    /* angles no farther apart than NODE_SPACING, between 2 and 5: an observer at eye height (2 m)
     * sees the ground over +-0.05 degrees of sun angle, where two suffice for the linear
     * interpolation (docs/decisions/2026-12-06-quadrature-accuracy.md) */
    return hi - lo < 1e-4 ? 1 : (int)fmin(5.0, fmax(2.0, ceil((hi - lo) / NODE_SPACING) + 1.0));
}

void ground_irradiance_add(ground_irradiance *g, const double *E)
{
    for (int n = 0; n < g->count; n++)
        spectral_add(&g->E[(size_t)n * g->K], E, g->K);
}

void ground_irradiance_free(ground_irradiance *g)
{
    free(g->E);
    g->E = NULL;
    g->count = 0;
}

void ground_irradiance_lookup(const ground_irradiance *g, double mu_s, double *E)
{
    const int K = g->K;
    double f = g->count == 1 ? 0.0 : (acos(fmin(1.0, fmax(-1.0, mu_s))) - g->theta0) / g->dtheta;
    f = fmin(fmax(f, 0.0), g->count - 1.0);
    int i = (int)f;
    if (i > g->count - 2)
        i = g->count > 1 ? g->count - 2 : 0;
    double t = g->count == 1 ? 0.0 : f - i;
    const double *a = &g->E[(size_t)i * K], *b = g->count == 1 ? a : a + K;
    for (int k = 0; k < K; k++)
        E[k] = a[k] * (1.0 - t) + b[k] * t;
}

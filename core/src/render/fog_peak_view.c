#include "render/fog_peak_view.h"

#include <math.h>

/* The light of n >= 2 scatterings in the peak, none wider, in a uniform layer of fog above the
 * observer (plane-parallel but for the sphere's slant at the horizon), by vertical optical depth x
 * from the fog's top: c_j(x) e^(-a_0 x) is the light's radiance after j of them, a_j the secant of
 * its direction, so that
 *     c_j' = -(a_j - a_0) c_j + w a_j c_(j-1),   c_0 = 1
 * (w: the peak's share of the extinction, per unit of the path after each turn).  With every a_j
 * = a_0 it is the table's Poisson term (w a_0 x)^j / j!.  The n scatterings split the turn from the
 * sun to the view equally: the j-th light's elevation lies j / n of the way, the mean path of the
 * small turns' random walk between the two ends (the whole turn at one scattering anywhere, or at
 * the last, overshoots one way or the other: docs/decisions/2026-12-07-fog-peak-split.md).  The
 * weight is sum_n c_n(tau) over its value at the sun's elevation, over the orders the sun's Poisson
 * mean holds. */
#define VIEW_STEPS 48       /* the fog's depth: the weights to 0.2 % of the closed form's */
#define VIEW_MAX_ORDER 64   /* where the light is not nil the mean is under 21 (peak share <= 0.6) */
#define VIEW_ORDER_SPREAD 6 /* orders within 6 (+ 6) standard deviations of the Poisson mean: all but 1e-9 */
/* The fog's depth along the sun's slant less its peak's (e^-14: the peak's light under a millionth
 * of the sun's): beyond, no weights (1), whose orders would cost most there. */
#define VIEW_NIL_DEPTH 14.0

/* The secant of elevation asin(mu) through a thin shell (2 H / R): 1 / mu but sqrt(2 R / H) at the
 * horizon. */
static double shell_secant(double mu, double shell)
{
    return 2.0 / (mu + sqrt(mu * mu + shell));
}

/* c_n(tau) for the secants a[0..n]: each step's exact exponential, the source linear across it. */
static double order_light(const double *a, int n, double tau, double w)
{
    double c[VIEW_MAX_ORDER + 1] = {1.0}, e[VIEW_MAX_ORDER + 1], p1[VIEW_MAX_ORDER + 1], p2[VIEW_MAX_ORDER + 1];
    const double h = tau / VIEW_STEPS;
    for (int j = 1; j <= n; j++) { /* int_0^h e^(-b (h - s)) (1, s / h) ds with b = a_j - a_0 */
        const double z = (a[j] - a[0]) * h;
        e[j] = exp(-z);
        const int small = fabs(z) < 1e-3;
        p1[j] = small ? h * (1.0 - z / 2.0 + z * z / 6.0) : -h * expm1(-z) / z;
        p2[j] = small ? h * (0.5 - z / 6.0 + z * z / 24.0) : h * (z + expm1(-z)) / (z * z);
    }
    for (int s = 0; s < VIEW_STEPS; s++) {
        double before = c[0]; /* c_(j-1) at the step's start; c_0 stays 1 */
        for (int j = 1; j <= n; j++) {
            const double start = c[j];
            c[j] = e[j] * start + w * a[j] * (before * (p1[j] - p2[j]) + c[j - 1] * p2[j]);
            before = start;
        }
    }
    return c[n];
}

/* sum_n c_n(tau) for the view at elevation ev, the sun at e0 (rad). */
static double view_light(double e0, double ev, double tau, double w, double shell, int n_lo, int n_hi)
{
    double sum = 0.0, a[VIEW_MAX_ORDER + 1];
    for (int n = n_lo; n <= n_hi; n++) {
        for (int j = 0; j <= n; j++)
            a[j] = shell_secant(sin(e0 + (ev - e0) * j / n), shell);
        sum += order_light(a, n, tau, w);
    }
    return sum;
}

void fog_peak_view_fill(double *w, double tau, double albedo, double shell, double mu0, double top_rad)
{
    w[0] = 0.0;
    w[1] = shell;
    if (!(tau > 0.0 && albedo > 0.0 && shell > 0.0 && mu0 > 0.0 && top_rad > 0.0))
        return;
    const double e0 = asin(fmin(mu0, 1.0)), a0 = shell_secant(mu0, shell), lambda = albedo * tau * a0;
    if ((1.0 - albedo) * tau * a0 > VIEW_NIL_DEPTH)
        return;
    const int n_lo = (int)fmax(2.0, floor(lambda - VIEW_ORDER_SPREAD * sqrt(lambda)));
    const int n_hi = (int)fmin(VIEW_MAX_ORDER, ceil(lambda + VIEW_ORDER_SPREAD * (sqrt(lambda) + 1.0)));
    if (n_lo > n_hi)
        return;
    const double sun = view_light(e0, e0, tau, albedo, shell, n_lo, n_hi);
    if (!(sun > 0.0) || !isfinite(sun))
        return;
    /* the nodes' spacing: the sun's elevation on a node (there the weight is 1), up to top_rad */
    w[0] = e0 / ceil(e0 / (top_rad / (FOG_PEAK_VIEWS - 1.0)));
    for (int i = 0; i < FOG_PEAK_VIEWS; i++) {
        const double L = view_light(e0, w[0] * i, tau, albedo, shell, n_lo, n_hi);
        w[2 + i] = L > 0.0 && isfinite(L) ? log(L / sun) : 0.0;
    }
}

fog_peak_view_place fog_peak_view_placed(const double *w, double mu)
{
    fog_peak_view_place p = {.spacing = w[0], .shell = w[1], .i = 0, .t = 0.0};
    if (!(w[0] > 0.0))
        return p;
    const double shell = w[1], e = mu > 0.0 ? asin(fmin(mu, 1.0)) : 0.0;
    p.i = (int)fmin(e / w[0], FOG_PEAK_VIEWS - 2.0);
    /* linear in the secant's inverse: smooth to the horizon, where the secant stays finite */
    const double x0 = 1.0 / shell_secant(sin(w[0] * p.i), shell), x1 = 1.0 / shell_secant(sin(w[0] * (p.i + 1)), shell);
    p.t = fmin(fmax((1.0 / shell_secant(fmax(mu, 0.0), shell) - x0) / (x1 - x0), 0.0), 1.0);
    return p;
}

double fog_peak_view_read(const double *w, const fog_peak_view_place *p)
{
    if (!(w[0] > 0.0))
        return 1.0;
    return exp(w[2 + p->i] + p->t * (w[3 + p->i] - w[2 + p->i]));
}

double fog_peak_view(const double *w, double mu)
{
    const fog_peak_view_place p = fog_peak_view_placed(w, mu);
    return fog_peak_view_read(w, &p);
}

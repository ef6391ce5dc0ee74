/* The weight of the fog's peak light by view (render/fog_peak_view.h), checked without the column:
 *  - at the sun's elevation it is 1 (the table's light, along the sun's slant, is kept);
 *  - against the closed form of its sum: the light after n scatterings in the peak with secants
 *    a_0 (the sun's) .. a_n (the view's) is w^n a_1 .. a_n e^(a_0 tau) times the integral over the
 *    fog's depth cut into n + 1 pieces u_i of e^(-sum a_i u_i), the divided difference
 *    sum_i e^(-a_i tau) / prod_(j != i) (a_j - a_i) (in long double; orders 2-10, all but 1e-5 of the
 *    Poisson sum at its mean of 2.2), within 0.3 % (the weight's depth steps) for fog of optical
 *    depth 1 at sun 12, 2-6 degrees below the sun and 4-8 above;
 *  - below the sun it dims, above it brightens, each the more the farther from the sun.
 * Fails with the table's light along the sun's slant for every view (the weight 1: 6 degrees below
 * the sun the closed form's 0.68) and with the whole turn at the last scattering (0.81 there). */
#include "check.h"

#include "render/fog_peak_view.h"

#include <math.h>
#include <stdio.h>

#define DEG (3.14159265358979323846 / 180.0)

/* The shell's secant, as the weight's (a thin shell of 2 H / R). */
static long double secant(double e, double shell)
{
    const long double mu = sinl((long double)e);
    return 2.0L / (mu + sqrtl(mu * mu + shell));
}

/* The closed form of sum_n c_n(tau) for the view at ev, the sun at e0 (rad), orders 2-10. */
static long double closed_light(double e0, double ev, double tau, double w, double shell)
{
    long double sum = 0.0L;
    for (int n = 2; n <= 10; n++) {
        long double a[11], dd = 0.0L, prod = 1.0L;
        for (int j = 0; j <= n; j++)
            a[j] = secant(e0 + (ev - e0) * j / n, shell);
        for (int i = 0; i <= n; i++) {
            long double den = 1.0L;
            for (int j = 0; j <= n; j++)
                den *= j == i ? 1.0L : a[j] - a[i];
            dd += expl(-a[i] * tau) / den;
        }
        for (int j = 1; j <= n; j++)
            prod *= w * a[j];
        sum += prod * expl(a[0] * tau) * dd;
    }
    return sum;
}

/* The table's light for the same orders (every secant a_0): (w a_0 tau)^n / n!. */
static long double table_light(double e0, double tau, double w, double shell)
{
    long double sum = 0.0L, term = 1.0L;
    const long double x = w * secant(e0, shell) * tau;
    for (int n = 1; n <= 10; n++) {
        term *= x / n;
        sum += n >= 2 ? term : 0.0L;
    }
    return sum;
}

static void weight_against_the_closed_form(void **state)
{
    (void)state;
    const double tau = 1.0, w = 0.45, e0 = 12.0 * DEG, shell = 2.0 * 200.0 / 6371e3;
    double table[FOG_PEAK_VIEW_SIZE];
    fog_peak_view_fill(table, tau, w, shell, sin(e0), e0 + 45.0 * DEG);
    check_abs(fog_peak_view(table, sin(e0)), 1.0, 1e-3, "the weight at the sun's elevation");
    const double offsets[] = {-6.0, -4.0, -2.0, 4.0, 8.0};
    double last_below = 0.0;
    for (int i = 0; i < 5; i++) {
        const double ev = e0 + offsets[i] * DEG;
        /* the weights' nodes lie 0.9 degrees apart: the closed form at the view itself */
        const double want = (double)(closed_light(e0, ev, tau, w, shell) / table_light(e0, tau, w, shell));
        const double got = fog_peak_view(table, sin(ev));
        char what[96];
        snprintf(what, sizeof what, "the weight %+g degrees from the sun", offsets[i]);
        printf("  %s: %.4f, closed form %.4f (%+.2f %%)\n", what, got, want, 100.0 * (got / want - 1.0));
        check_abs(got, want, 3e-3 * want, what);
        assert_true(offsets[i] < 0.0 ? got < 1.0 && got > last_below : got > 1.0);
        last_below = offsets[i] < 0.0 ? got : last_below;
    }
    assert_true(fog_peak_view(table, sin(e0 + 8.0 * DEG)) > fog_peak_view(table, sin(e0 + 4.0 * DEG)));
}

/* No fog above the observer: every weight 1. */
static void no_fog_no_weight(void **state)
{
    (void)state;
    double table[FOG_PEAK_VIEW_SIZE];
    fog_peak_view_fill(table, 0.0, 0.45, 1e-4, sin(10.0 * DEG), 55.0 * DEG);
    check_abs(fog_peak_view(table, sin(4.0 * DEG)), 1.0, 0.0, "no fog");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(weight_against_the_closed_form),
        cmocka_unit_test(no_fog_no_weight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

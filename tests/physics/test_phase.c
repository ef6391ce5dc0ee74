/* Rayleigh phase function: normalisation, and its sampler against its density (chi-square). */
#include "check.h"

#include "base/rng.h"
#include "base/units.h"
#include "phase/phase_rayleigh.h"

#include <math.h>

static void normalised_over_the_sphere(void **state)
{
    const double gammas[] = {0.0, 0.0144, 0.05};
    for (int i = 0; i < 3; i++) {
        double s = 0.0;
        const int n = 100000;
        for (int j = 0; j < n; j++) {
            double mu = -1.0 + (j + 0.5) * 2.0 / n;
            s += phase_rayleigh_eval(mu, gammas[i]) * 2.0 * FM_PI * 2.0 / n;
        }
        check_abs(s, 1.0, 1e-9, "integral of the Rayleigh phase function");
    }
    check_abs(phase_rayleigh_eval(1.0, 0.0), 3.0 / (8.0 * FM_PI), 1e-15, "classic 3/16pi (1 + cos^2) forward");
}

/* Pearson chi-square over 50 bins of cos(theta): with 49 degrees of freedom the 99.9% point is
 * 85.4.  A sampler that ignored the phase function (uniform directions) gives thousands. */
static void sampler_matches_density(void **state)
{
    const double gamma = 0.0144;
    const int bins = 50, n = 2000000;
    double counts[50] = {0};
    rng r = rng_for(9, 9, 9);
    for (int i = 0; i < n; i++) {
        double mu = phase_rayleigh_sample(rng_uniform(&r), gamma);
        assert_true(mu >= -1.0 && mu <= 1.0);
        int b = (int)((mu + 1.0) * 0.5 * bins);
        counts[b < bins ? b : bins - 1] += 1.0;
    }
    double chi2 = 0.0;
    for (int b = 0; b < bins; b++) {
        /* expected count: integral of the density over the bin (Simpson, exact for a quadratic) */
        double a = -1.0 + 2.0 * b / bins, c = a + 2.0 / bins, m = 0.5 * (a + c);
        double p = (c - a) / 6.0 *
                   (phase_rayleigh_eval(a, gamma) + 4 * phase_rayleigh_eval(m, gamma) + phase_rayleigh_eval(c, gamma)) *
                   2.0 * FM_PI;
        double expect = p * n;
        chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
    }
    print_message("chi-square = %.1f (49 degrees of freedom)\n", chi2);
    assert_true(chi2 < 85.4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(normalised_over_the_sphere),
        cmocka_unit_test(sampler_matches_density),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

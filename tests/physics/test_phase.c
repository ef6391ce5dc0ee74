/* Phase functions: normalisation of every kind, each sampler against its density (chi-square),
 * Henyey-Greenstein sampling near g = 0 and in the forward peak, tabulated functions against the
 * function they were built from, one-search evaluation of all wavelengths, and refused tables. */
#include "check.h"

#include "base/rng.h"
#include "base/units.h"
#include "phase/phase.h"
#include "phase/phase_hg.h"
#include "phase/phase_rayleigh.h"
#include "phase/phase_table.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* 2 pi * integral over [-1, 1] of f(mu) p(mu) dmu with f = mu^power, by composite Simpson in x with
 * mu = 1 - 2 x^3: nodes crowd near the forward direction, where HG g = 0.99 peaks within 1e-4 of
 * mu = 1.  Independent of the phase functions' own normalisation and tables. */
static double sphere_moment(const phase_function *p, int k, int power)
{
    const int n = 400000; /* even */
    double s = 0.0;
    for (int i = 0; i <= n; i++) {
        double x = (double)i / n, mu = 1.0 - 2.0 * x * x * x, jac = 6.0 * x * x;
        double f = phase_evaluate(p, k, mu) * jac * (power ? mu : 1.0);
        s += f * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    return 2.0 * FM_PI * s / (3.0 * n);
}

static phase_function hg(double g)
{
    phase_function p = {.kind = PHASE_HENYEY_GREENSTEIN};
    p.param[0] = g;
    return p;
}

/* HG values at n angles theta_j = pi (j / (n-1))^2 (fine near the forward direction). */
static void hg_table_values(double g, int n, double *theta, double *values)
{
    for (int j = 0; j < n; j++) {
        double t = (double)j / (n - 1);
        theta[j] = FM_PI * t * t;
        values[j] = phase_hg_eval(cos(theta[j]), g);
    }
}

static phase_function hg_table(double g, int n)
{
    double *theta = malloc(n * sizeof *theta), *values = malloc(n * sizeof *values);
    assert_non_null(theta);
    assert_non_null(values);
    hg_table_values(g, n, theta, values);
    phase_function p = {0};
    fm_error err;
    assert_int_equal(phase_init_tabulated(&p, 1, n, theta, values, &err), FM_OK);
    free(theta);
    free(values);
    return p;
}

/* A table with a ramp, a steep step (1 -> 0 over 1 mrad), a zero plateau from 1.001 to 2 rad, and a
 * density rising from zero to the backward direction; given in an arbitrary normalisation. */
static phase_function step_table(void)
{
    const double theta[] = {0.0, 0.5, 1.0, 1.001, 2.0, FM_PI};
    const double values[] = {30.0, 10.0, 10.0, 0.0, 0.0, 20.0};
    phase_function p = {0};
    fm_error err;
    assert_int_equal(phase_init_tabulated(&p, 1, 6, theta, values, &err), FM_OK);
    return p;
}

static void normalised_over_the_sphere(void **state)
{
    const double gammas[] = {0.0, 0.0144, 0.05};
    for (int i = 0; i < 3; i++) {
        phase_function p = {.kind = PHASE_RAYLEIGH};
        p.param[0] = gammas[i];
        check_abs(sphere_moment(&p, 0, 0), 1.0, 1e-9, "integral of the Rayleigh phase function");
    }
    check_abs(phase_rayleigh_eval(1.0, 0.0), 3.0 / (8.0 * FM_PI), 1e-15, "classic 3/16pi (1 + cos^2) forward");

    const double gs[] = {0.99, 0.95, 0.8, 1e-9, 0.0, -0.3, -0.9};
    for (int i = 0; i < 7; i++) {
        phase_function p = hg(gs[i]);
        check_abs(sphere_moment(&p, 0, 0), 1.0, 1e-6, "integral of the Henyey-Greenstein phase function");
        check_abs(sphere_moment(&p, 0, 1), gs[i], 1e-6, "mean cos_theta of HG is g");
        assert_true(phase_asymmetry(&p, 0) == gs[i]);
    }
    check_abs(phase_hg_eval(0.3, 0.0), 1.0 / (4.0 * FM_PI), 1e-17, "HG g = 0 is isotropic");

    phase_function t = hg_table(0.95, 257);
    check_abs(sphere_moment(&t, 0, 0), 1.0, 1e-6, "integral of a tabulated forward-peaked function");
    phase_free(&t);
    t = step_table();
    check_abs(sphere_moment(&t, 0, 0), 1.0, 1e-6, "integral of a tabulated function with a step");
    phase_free(&t);

    phase_function none = {.kind = PHASE_NONE};
    check_abs(sphere_moment(&none, 0, 0), 0.0, 0.0, "an absorber does not scatter");
}

/* Pearson chi-square of N samples of cos_theta over bins [edge_b, edge_b+1] (ascending from -1 to 1);
 * the expected count is N times the bin's integral of the density (Simpson, 1000 steps per bin).
 * Bins the density gives no weight must stay empty; the rest count towards the degrees of freedom.
 * The 99.9% point of chi-square comes from the Wilson-Hilferty approximation,
 * nu (1 - 2/(9 nu) + z sqrt(2/(9 nu)))^3 with z = 3.0902 (85.4 for nu = 49, as tabulated). */
static void check_sampler(const phase_function *p, int k, const double *edge, int bins, int N, uint64_t seed,
                          const char *what)
{
    double *counts = calloc(bins, sizeof *counts);
    assert_non_null(counts);
    rng r = rng_for(seed, 1, 2);
    for (int i = 0; i < N; i++) {
        double mu = phase_sample(p, k, rng_uniform(&r));
        assert_true(mu >= -1.0 && mu <= 1.0);
        int lo = 0, hi = bins; /* last edge <= mu */
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if (edge[mid] <= mu)
                lo = mid;
            else
                hi = mid;
        }
        counts[lo] += 1.0;
    }
    double chi2 = 0.0;
    int used = 0;
    for (int b = 0; b < bins; b++) {
        const int m = 1000;
        double a = edge[b], h = (edge[b + 1] - a) / m, s = 0.0;
        for (int i = 0; i <= m; i++)
            s += phase_evaluate(p, k, a + i * h) * (i == 0 || i == m ? 1.0 : (i % 2 ? 4.0 : 2.0));
        double expect = N * 2.0 * FM_PI * s * h / 3.0;
        if (expect == 0.0) {
            assert_true(counts[b] == 0.0);
            continue;
        }
        chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
        used++;
    }
    double nu = used - 1, c = 2.0 / (9.0 * nu), limit = nu * pow(1.0 - c + 3.0902 * sqrt(c), 3.0);
    print_message("%s: chi-square = %.1f (%d degrees of freedom, 99.9%% point %.1f)\n", what, chi2, (int)nu, limit);
    assert_true(chi2 < limit);
    free(counts);
}

/* Bin edges in cos_theta: uniform, or 1 - 2 (1 - i/B)^2 (width 2/B^2 next to the forward direction). */
static void edges(double *e, int bins, int forward_fine)
{
    for (int i = 0; i <= bins; i++) {
        double t = 1.0 - (double)i / bins;
        e[i] = forward_fine ? 1.0 - 2.0 * t * t : -1.0 + 2.0 * i / bins;
    }
    e[0] = -1.0;
    e[bins] = 1.0;
}

static void rayleigh_sampler_matches_density(void **state)
{
    double e[51];
    edges(e, 50, 0);
    phase_function p = {.kind = PHASE_RAYLEIGH};
    p.param[0] = 0.0144;
    check_sampler(&p, 0, e, 50, 2000000, 9, "Rayleigh");
}

static void hg_sampler_matches_density(void **state)
{
    double e[201];
    edges(e, 100, 1);
    phase_function p = hg(0.8);
    check_sampler(&p, 0, e, 100, 2000000, 11, "HG g = 0.8");
    p = hg(0.99);
    check_sampler(&p, 0, e, 100, 2000000, 12, "HG g = 0.99");
    edges(e, 50, 0);
    p = hg(-0.3);
    check_sampler(&p, 0, e, 50, 2000000, 13, "HG g = -0.3");
    p = hg(0.0);
    check_sampler(&p, 0, e, 50, 2000000, 14, "HG g = 0");
}

/* The sampler inverts the closed-form CDF P(cos <= mu) = (1 - g^2) / (2 g) ((1 + g^2 - 2 g mu)^-1/2 -
 * 1 / (1 + g)) to rounding, including in the forward peak of g = 0.99; near g = 0 (where that form and
 * the textbook inverse lose digits) it tends to the isotropic mu = 2u - 1. */
static void hg_sampler_inverts_cdf(void **state)
{
    const double gs[] = {0.99, 0.8, 1e-3, -0.3, -0.95};
    for (int i = 0; i < 5; i++) {
        double g = gs[i], worst = 0.0, prev = -2.0;
        for (int j = 0; j <= 10000; j++) {
            double u = j < 10000 ? j / 10000.0 : 1.0 - 1e-12;
            double mu = phase_hg_sample(u, g);
            double F = (1.0 - g * g) / (2.0 * g) * (1.0 / sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g));
            worst = fmax(worst, fabs(F - u));
            assert_true(mu >= prev); /* monotone in u */
            prev = mu;
        }
        print_message("g = %g: largest |CDF(sample(u)) - u| = %.2e\n", g, worst);
        assert_true(worst < 1e-10);
    }
    double worst = 0.0;
    for (int j = 0; j <= 100; j++) {
        double u = j / 100.0;
        assert_true(phase_hg_sample(u, 0.0) == 2.0 * u - 1.0);
        worst = fmax(worst, fabs(phase_hg_sample(u, 1e-12) - (2.0 * u - 1.0)));
        worst = fmax(worst, fabs(phase_hg_sample(u, -1e-12) - (2.0 * u - 1.0)));
    }
    check_abs(worst, 0.0, 1e-11, "largest |sample - (2u - 1)| for g = +-1e-12");
}

static void table_sampler_matches_density(void **state)
{
    double e[201];
    edges(e, 200, 1);
    phase_function t = hg_table(0.95, 257);
    check_sampler(&t, 0, e, 200, 2000000, 21, "table of HG g = 0.95, 257 angles");
    phase_free(&t);
    edges(e, 64, 0);
    t = step_table();
    check_sampler(&t, 0, e, 64, 2000000, 22, "table with a step and a zero plateau");
    phase_free(&t);
}

/* Built from HG g = 0.8 at 2001 angles, the table matches HG everywhere (nodes and between them) and
 * its exact asymmetry matches g; that asymmetry also equals an independent quadrature of mu p. */
static void table_reproduces_hg(void **state)
{
    const double gs[] = {0.8, 0.95};
    const int ns[] = {2001, 257};
    for (int i = 0; i < 2; i++) {
        phase_function t = hg_table(gs[i], ns[i]);
        double worst = 0.0;
        for (int j = 0; j <= 100000; j++) {
            double s = j / 100000.0, mu = cos(FM_PI * s * s);
            double ref = phase_hg_eval(mu, gs[i]);
            worst = fmax(worst, fabs(phase_evaluate(&t, 0, mu) / ref - 1.0));
        }
        double g = phase_asymmetry(&t, 0);
        print_message("HG g = %g from %d angles: largest relative error %.2e, asymmetry %.6f\n", gs[i], ns[i], worst,
                      g);
        if (ns[i] > 1000)
            assert_true(worst < 1e-3);
        check_abs(g, gs[i], 1e-3, "asymmetry of a tabulated HG");
        check_abs(g, sphere_moment(&t, 0, 1), 1e-7, "exact asymmetry of the piecewise-linear function");
        phase_free(&t);
    }
    phase_function t = step_table();
    check_abs(phase_asymmetry(&t, 0), sphere_moment(&t, 0, 1), 1e-7, "asymmetry of the step table");
    phase_free(&t);
}

/* phase_evaluate_all gives, bit for bit, what phase_evaluate gives wavelength by wavelength. */
/* phase_table_bin starts from a coarse index and moves to the exact bin: it must give the bin that a
 * search gives (the largest j <= n-2 with mu_j >= cos_theta, else 0) for every cos_theta, nodes,
 * their neighbouring doubles and the ends included, on the aerosol tables' grid, a uniform grid and a
 * six-angle one. */
static void table_bin_is_the_searched_bin(void **state)
{
    phase_function tables[3] = {hg_table(0.8, 301), {0}, step_table()};
    double theta[181], values[181];
    for (int j = 0; j < 181; j++) {
        theta[j] = FM_PI * j / 180.0;
        values[j] = 1.0 + cos(theta[j]);
    }
    fm_error err;
    assert_int_equal(phase_init_tabulated(&tables[1], 1, 181, theta, values, &err), FM_OK);
    rng r = rng_for(7, 8, 9);
    for (int i = 0; i < 3; i++) {
        const phase_table *t = tables[i].table;
        const int n = t->angle_count;
        for (int q = -6; q < 3 * n + 20000; q++) {
            double c;
            if (q < 0)
                c = (double[]){-1.0, 1.0, 1.5, -1.5, NAN, 0.0}[q + 6];
            else if (q < 3 * n)
                c = q % 3 == 0 ? t->mu[q / 3] : nextafter(t->mu[q / 3], q % 3 == 1 ? 2.0 : -2.0);
            else
                c = 2.0 * rng_uniform(&r) - 1.0;
            int expected = 0;
            for (int j = 0; j + 1 < n; j++)
                if (t->mu[j] >= c)
                    expected = j;
            if (phase_table_bin(t, c) != expected)
                fail_msg("table %d, cos_theta %.17g: bin %d, searched %d", i, c, phase_table_bin(t, c), expected);
        }
        phase_free(&tables[i]);
    }
}

static void evaluate_all_matches_evaluate(void **state)
{
    const int K = 3, n = 101;
    const double gs[] = {0.2, 0.6, 0.9};
    double theta[101], values[3 * 101];
    for (int k = 0; k < K; k++)
        hg_table_values(gs[k], n, theta, values + k * n);
    phase_function kinds[4] = {{.kind = PHASE_RAYLEIGH}, {.kind = PHASE_HENYEY_GREENSTEIN}, {0}, {.kind = PHASE_NONE}};
    fm_error err;
    assert_int_equal(phase_init_tabulated(&kinds[2], K, n, theta, values, &err), FM_OK);
    for (int k = 0; k < K; k++) {
        kinds[0].param[k] = 0.01 * (k + 1);
        kinds[1].param[k] = gs[k] - 0.5;
    }
    for (int i = 0; i < 4; i++)
        for (int j = -2; j <= 2002; j++) {
            double mu = j <= 1000 ? -1.0 + j * 0.002 : cos(theta[(j - 1001) % n]); /* also every node */
            double all[3];
            phase_evaluate_all(&kinds[i], K, mu, all);
            for (int k = 0; k < K; k++)
                assert_true(all[k] == phase_evaluate(&kinds[i], k, mu));
        }
    check_abs(phase_asymmetry(&kinds[0], 1), 0.0, 0.0, "Rayleigh is symmetric");
    check_abs(phase_asymmetry(&kinds[3], 1), 0.0, 0.0, "an absorber has no asymmetry");
    phase_free(&kinds[2]);
    assert_null(kinds[2].table);
    assert_int_equal(kinds[2].kind, PHASE_TABULATED);
}

static void refuse(int K, int n, const double *theta, const double *values, const char *what)
{
    phase_function p = {0};
    fm_error err = {0};
    fm_status st = phase_init_tabulated(&p, K, n, theta, values, &err);
    print_message("%s: %s\n", what, err.message);
    assert_int_equal(st, FM_ERR_INVALID_ARGUMENT);
    assert_true(err.message[0] != '\0');
    assert_null(p.table);
    assert_int_equal(p.kind, PHASE_NONE);
}

static void bad_tables_are_refused(void **state)
{
    const double theta[] = {0.0, 1.0, 2.0, FM_PI};
    const double good[] = {1.0, 1.0, 1.0, 1.0, 2.0, 1.0, 0.5, 0.1};
    double v[8];
#define WITH(idx, val) (memcpy(v, good, sizeof v), v[idx] = (val), v)
    refuse(2, 4, theta, WITH(5, -1e-3), "negative value");
    refuse(2, 4, theta, WITH(2, NAN), "NaN value");
    refuse(2, 4, theta, WITH(7, INFINITY), "infinite value");
#undef WITH
    const double zero_second[] = {1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0};
    refuse(2, 4, theta, zero_second, "a wavelength that is all zero");
    const double repeated[] = {0.0, 1.0, 1.0, FM_PI}, descending[] = {0.0, 2.0, 1.0, FM_PI};
    refuse(2, 4, repeated, good, "repeated angle");
    refuse(2, 4, descending, good, "descending angles");
    const double late[] = {0.1, 1.0, 2.0, FM_PI}, short_[] = {0.0, 1.0, 2.0, 3.0}, nan_t[] = {0.0, NAN, 2.0, FM_PI};
    refuse(2, 4, late, good, "first angle not 0");
    refuse(2, 4, short_, good, "last angle not pi");
    refuse(2, 4, nan_t, good, "NaN angle");
    const double degrees[] = {0.0, 60.0, 120.0, 180.0};
    refuse(2, 4, degrees, good, "angles in degrees");
    refuse(2, 1, theta, good, "one angle");
    refuse(0, 4, theta, good, "no wavelength");
    refuse(FM_MAX_WAVELENGTHS + 1, 4, theta, good, "too many wavelengths");

    phase_function p = {0};
    fm_error err;
    assert_int_equal(phase_init_tabulated(&p, 2, 4, theta, good, &err), FM_OK);
    phase_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(normalised_over_the_sphere),
        cmocka_unit_test(rayleigh_sampler_matches_density),
        cmocka_unit_test(hg_sampler_matches_density),
        cmocka_unit_test(hg_sampler_inverts_cdf),
        cmocka_unit_test(table_sampler_matches_density),
        cmocka_unit_test(table_reproduces_hg),
        cmocka_unit_test(table_bin_is_the_searched_bin),
        cmocka_unit_test(evaluate_all_matches_evaluate),
        cmocka_unit_test(bad_tables_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

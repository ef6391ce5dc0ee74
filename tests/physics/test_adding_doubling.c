/* The adding-doubling reference (adding_doubling.c) against published values and exact limits, before
 * the path tracer is compared with it (test_thick_media.c):
 *  - isotropic scattering, albedo 0.8, optical depth 2: van de Hulst (1980), "Multiple Light
 *    Scattering", vol. 1, Table 12 (pp. 260-261), reflection R(0.5, mu0) and diffuse transmission
 *    T(0.5, mu0) to the table's 5 digits;
 *  - a semi-infinite isotropic layer (tau 100, albedo 0.9): R(mu, mu0) = (w / 4) H(mu) H(mu0) /
 *    (mu + mu0) with Chandrasekhar's H-function solved here from its integral equation (Chandrasekhar
 *    1950, "Radiative Transfer", eq. V.(11)), whose conservative value H(1) = 2.9078 (his Table XIII)
 *    checks the iteration;
 *  - the single-scattering limit (tau 1e-5, Henyey-Greenstein g 0.5 and 0.85 expanded in full, 0.9
 *    truncated by delta-M with its exact single scattering), in closed form;
 *  - conservative scattering: R + T = 1 over a black ground, and R = 1 over a white one (HG g 0.85
 *    and 0.9, optical depths 10 and 100);
 *  - reciprocity: mu0 R(mu, mu0, phi) is symmetric in mu and mu0;
 *  - convergence in the number of streams for the cases the path tracer is compared with, and
 *    delta-M with its exact single scattering against the full expansion. */
#include "check.h"

#include "adding_doubling.h"

#include <math.h>
#include <stdio.h>

static double iso(double x, const void *ctx)
{
    (void)x;
    (void)ctx;
    return 1.0;
}

static ad_solution solve(double tau, double ssa, double albedo, double mu0, ad_phase_fn ph, const void *ctx,
                         int streams, int delta_m, int n_mu, const double *mu)
{
    ad_problem p = {.tau = tau, .ssa = ssa, .ground_albedo = albedo, .mu0 = mu0, .phase = ph, .phase_ctx = ctx,
                    .streams = streams, .delta_m = delta_m, .n_mu = n_mu, .mu = mu};
    ad_solution s;
    assert_int_equal(ad_solve(&p, &s), 0);
    return s;
}

static void test_van_de_hulst_table_12(void **state)
{
    (void)state;
    static const double mu0[6] = {1.0, 0.9, 0.7, 0.5, 0.3, 0.1};
    static const double R[6] = {0.28616, 0.30277, 0.34188, 0.39102, 0.45353, 0.53214};
    static const double T[6] = {0.14864, 0.14731, 0.13963, -1.0, 0.09425, 0.06601}; /* -1: not listed */
    double view = 0.5;
    for (int i = 0; i < 6; i++) {
        ad_solution s = solve(2.0, 0.8, 0.0, mu0[i], iso, NULL, 16, 0, 1, &view);
        char what[64];
        snprintf(what, sizeof what, "R(0.5, %.1f)", mu0[i]);
        check_abs(FM_PI * ad_radiance_top(&s, 0, 0.0) / mu0[i], R[i], 1e-5, what);
        if (T[i] > 0) {
            snprintf(what, sizeof what, "T(0.5, %.1f)", mu0[i]);
            check_abs(FM_PI * ad_radiance_bottom(&s, 0, 0.0) / mu0[i], T[i], 1e-5, what);
        }
        ad_free(&s);
    }
}

/* H(mu) on Gauss nodes by 1/H(mu) = sqrt(1 - w) + (w/2) int_0^1 mu' H(mu') / (mu + mu') dmu'. */
#define HN 400
static void h_function(double w, const double *x, const double *c, double *h)
{
    for (int i = 0; i < HN; i++)
        h[i] = 1.0;
    for (int it = 0; it < 2000; it++)
        for (int i = 0; i < HN; i++) {
            double sum = 0.0;
            for (int j = 0; j < HN; j++)
                sum += c[j] * x[j] * h[j] / (x[i] + x[j]);
            h[i] = 1.0 / (sqrt(1.0 - w) + 0.5 * w * sum);
        }
}

static double h_at(double w, double mu, const double *x, const double *c, const double *h)
{
    double sum = 0.0;
    for (int j = 0; j < HN; j++)
        sum += c[j] * x[j] * h[j] / (mu + x[j]);
    return 1.0 / (sqrt(1.0 - w) + 0.5 * w * sum);
}

static void test_chandrasekhar_h(void **state)
{
    (void)state;
    static double x[HN], c[HN], h[HN];
    for (int i = 0; i < HN; i++) { /* midpoint nodes in mu = t^2 (denser near 0, where H is steepest) */
        double t = (i + 0.5) / HN;
        x[i] = t * t;
        c[i] = 2.0 * t / HN;
    }
    h_function(1.0, x, c, h);
    check_rel(h_at(1.0, 1.0, x, c, h), 2.9078, 2e-4, "H(1), conservative isotropic (Chandrasekhar Table XIII)");
    double w = 0.9, mu[4] = {0.15, 0.4, 0.75, 1.0};
    h_function(w, x, c, h);
    for (int a = 0; a < 4; a++) {
        ad_solution s = solve(100.0, w, 0.0, mu[a], iso, NULL, 16, 0, 4, mu);
        for (int b = 0; b < 4; b++) {
            double exact = 0.25 * w * h_at(w, mu[a], x, c, h) * h_at(w, mu[b], x, c, h) / (mu[a] + mu[b]);
            char what[64];
            snprintf(what, sizeof what, "semi-infinite R(%.2f, %.2f)", mu[b], mu[a]);
            check_rel(FM_PI * ad_radiance_top(&s, b, 0.0) / mu[a], exact, 2e-4, what);
        }
        ad_free(&s);
    }
}

static void single_scattering(double g, int streams, int delta_m)
{
    double tau = 1e-5, ssa = 0.9, mu0 = 0.6, mu[3] = {0.25, 0.6, 0.95};
    ad_solution s = solve(tau, ssa, 0.0, mu0, ad_phase_hg, &g, streams, delta_m, 3, mu);
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 5; a++) {
            double phi = a * FM_PI / 4.0, sn = sqrt((1.0 - mu[k] * mu[k]) * (1.0 - mu0 * mu0));
            double pt = ad_phase_hg(mu[k] * mu0 + sn * cos(phi), &g), pr = ad_phase_hg(-mu[k] * mu0 + sn * cos(phi), &g);
            double d = mu[k] - mu0, f = fabs(d) < 1e-12 ? tau / (mu0 * mu0) : expm1(tau * d / (mu[k] * mu0)) / d;
            double down = ssa * pt * mu0 * exp(-tau / mu0) * f;
            double up = ssa * pr * mu0 / (mu[k] + mu0) * -expm1(-tau * (mu[k] + mu0) / (mu[k] * mu0));
            char what[96];
            snprintf(what, sizeof what, "single scattering g %.2f down mu %.2f phi %.0f", g, mu[k], phi / FM_DEG);
            check_rel(ad_radiance_bottom(&s, k, phi), down, 2e-4, what);
            snprintf(what, sizeof what, "single scattering g %.2f up mu %.2f phi %.0f", g, mu[k], phi / FM_DEG);
            check_rel(ad_radiance_top(&s, k, phi), up, 2e-4, what);
        }
    ad_free(&s);
}

static void test_single_scattering_limit(void **state)
{
    (void)state;
    single_scattering(0.5, 24, 0);  /* 0.5^48: the expansion is exact */
    single_scattering(0.85, 64, 0); /* 0.85^128 = 9e-10 */
    single_scattering(0.9, 8, 1);   /* truncated at 16 moments: the exact single scattering (TMS) */
}

static void test_conservation(void **state)
{
    (void)state;
    double gs[2] = {0.85, 0.9}, taus[2] = {10.0, 100.0};
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++)
            for (int dm = 0; dm < 2; dm++) {
                ad_solution s = solve(taus[b], 1.0, 0.0, 0.5, ad_phase_hg, &gs[a], 16, dm, 0, NULL);
                char what[96];
                snprintf(what, sizeof what, "R + T, g %.2f tau %.0f delta-M %d", gs[a], taus[b], dm);
                check_abs(s.flux_up_top + s.flux_down_diffuse + s.flux_down_direct, 1.0, 2e-6, what);
                ad_free(&s);
                s = solve(taus[b], 1.0, 1.0, 0.5, ad_phase_hg, &gs[a], 16, dm, 0, NULL);
                snprintf(what, sizeof what, "R over a white ground, g %.2f tau %.0f delta-M %d", gs[a], taus[b], dm);
                check_abs(s.flux_up_top, 1.0, 2e-5, what);
                ad_free(&s);
            }
}

static void test_reciprocity(void **state)
{
    (void)state;
    double g = 0.85, a = 0.3, b = 0.8;
    ad_solution s1 = solve(5.0, 0.99, 0.0, a, ad_phase_hg, &g, 16, 1, 1, &b);
    ad_solution s2 = solve(5.0, 0.99, 0.0, b, ad_phase_hg, &g, 16, 1, 1, &a);
    for (int k = 0; k < 7; k++) {
        double phi = k * FM_PI / 6.0;
        check_rel(ad_radiance_top(&s1, 0, phi) / a, ad_radiance_top(&s2, 0, phi) / b, 1e-8, "R(mu, mu0) = R(mu0, mu)");
        check_rel(ad_radiance_bottom(&s1, 0, phi) / a, ad_radiance_bottom(&s2, 0, phi) / b, 1e-8, "T(mu, mu0) = T(mu0, mu)");
    }
    ad_free(&s1);
    ad_free(&s2);
}

/* N streams against 2N at views 15-80 degrees up, away from the sun's aureole, HG g 0.9: the stream
 * counts test_thick_media uses (32 at tau 2, where the truncated peak matters most; 16 beyond). */
static void test_stream_convergence(void **state)
{
    (void)state;
    double g = 0.9, taus[3] = {2.0, 10.0, 100.0}, mu[6];
    for (int k = 0; k < 6; k++)
        mu[k] = sin((15.0 + 13.0 * k) * FM_DEG);
    for (int t = 0; t < 3; t++) {
        int n = taus[t] < 5.0 ? 32 : 16;
        ad_solution a = solve(taus[t], 0.99999, 0.2, 0.5, ad_phase_hg, &g, n, 1, 6, mu);
        ad_solution b = solve(taus[t], 0.99999, 0.2, 0.5, ad_phase_hg, &g, 2 * n, 1, 6, mu);
        for (int k = 0; k < 6; k++)
            for (int p = 0; p < 3; p++) {
                double phi = (90.0 + 45.0 * p) * FM_DEG;
                char what[96];
                snprintf(what, sizeof what, "%d vs %d streams, tau %.0f mu %.2f phi %.0f", n, 2 * n, taus[t], mu[k],
                         phi / FM_DEG);
                check_rel(ad_radiance_bottom(&a, k, phi), ad_radiance_bottom(&b, k, phi), 1e-3, what);
                check_rel(ad_radiance_top(&a, k, phi), ad_radiance_top(&b, k, phi), 1e-3, what);
            }
        check_rel(a.flux_down_diffuse, b.flux_down_diffuse, 1e-4, "diffuse transmittance, N vs 2N streams");
        ad_free(&a);
        ad_free(&b);
    }
    /* delta-M with its exact single scattering against the plain expansion at 64 streams, whose 128
     * moments hold HG g 0.85 to 0.85^128 = 9e-10 */
    g = 0.85;
    ad_solution a = solve(2.0, 1.0, 0.3, 0.5, ad_phase_hg, &g, 32, 1, 6, mu);
    ad_solution b = solve(2.0, 1.0, 0.3, 0.5, ad_phase_hg, &g, 64, 0, 6, mu);
    for (int k = 0; k < 6; k++)
        for (int p = 0; p < 3; p++) {
            double phi = (90.0 * p) * FM_DEG;
            char what[96];
            snprintf(what, sizeof what, "delta-M 32 vs plain 64 streams, tau 2 mu %.2f phi %.0f", mu[k], phi / FM_DEG);
            check_rel(ad_radiance_bottom(&a, k, phi), ad_radiance_bottom(&b, k, phi), 1e-3, what);
            check_rel(ad_radiance_top(&a, k, phi), ad_radiance_top(&b, k, phi), 1e-3, what);
        }
    ad_free(&a);
    ad_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_van_de_hulst_table_12), cmocka_unit_test(test_chandrasekhar_h),
        cmocka_unit_test(test_single_scattering_limit), cmocka_unit_test(test_conservation),
        cmocka_unit_test(test_reciprocity), cmocka_unit_test(test_stream_convergence),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

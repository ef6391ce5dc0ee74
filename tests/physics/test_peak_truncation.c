/* The forward peak truncated for the fast path's multiple scattering under a deck (delta-M,
 * aerosol/cloud_layer.h, sky.h), checked without the path tracer:
 *  - the adding-doubling solution (adding_doubling.h) of a stratus layer at 550 nm with its full Mie
 *    phase function and that of the truncated layer (phase cut within 3 degrees, optical depth
 *    tau (1 - f w), albedo w (1 - f) / (1 - f w)) give the same diffuse radiances under the layer and
 *    the same diffuse irradiance at the ground within 0.1 % (optical depths 30 and 100, sun 30 and 60
 *    degrees up, ground albedo 0.15; they differ by 4e-4 to 5.4e-4, as the similarity parameter's
 *    change f (1 - <cos>_peak) / (1 - g) = 5.7e-4 says): what the truncation moves is nothing the
 *    light under a deck shows;
 *  - the truncated fraction: cutting the peak conserves the light (f + (1 - f) times the cut
 *    function's integral is 1) and moves the asymmetry parameter as delta-M does,
 *    g = f <cos>_peak + (1 - f) g', with <cos>_peak between cos(3 degrees) and 1;
 *  - a sky with a layer of optical depth 25 or more builds the truncated copy, its scattering
 *    coefficient at 550 nm (1 - f) times the sky's own; thinner layers and clear skies build none. */
#include "check.h"

#include "adding_doubling.h"
#include "aerosol/cloud.h"
#include "aerosol/cloud_layer.h"
#include "base/units.h"
#include "phase/phase.h"
#include "sky.h"

#include <math.h>
#include <stdio.h>

/* The stratus phase values at 550 nm (CLOUD_ANGLE_COUNT of them at cloud_angle_rad), the
 * single-scattering albedo and the angles. */
static double stratus_550(double *values, double *theta)
{
    mie_lognormal_result r;
    fm_error err;
    if (cloud_water_optics(cloud_type_find("stratus"), 550.0, &r, values, &err))
        fail_msg("%s", err.message);
    for (int j = 0; j < CLOUD_ANGLE_COUNT; j++)
        theta[j] = cloud_angle_rad(j);
    return r.sca_m2 / r.ext_m2;
}

static double table_phase(double cos_theta, const void *ctx)
{
    return phase_evaluate(ctx, 0, cos_theta);
}

static void tabulate(phase_function *p, const double *values, const double *theta)
{
    fm_error err;
    if (phase_init_tabulated(p, 1, CLOUD_ANGLE_COUNT, theta, values, &err))
        fail_msg("%s", err.message);
}

static ad_solution solve(double tau, double ssa, double mu0, const phase_function *p, int n_mu, const double *mu)
{
    ad_problem pr = {.tau = tau, .ssa = ssa, .ground_albedo = 0.15, .mu0 = mu0, .phase = table_phase,
                     .phase_ctx = p, .streams = 32, .delta_m = 1, .n_mu = n_mu, .mu = mu};
    ad_solution s;
    if (ad_solve(&pr, &s))
        fail_msg("ad_solve failed");
    return s;
}

static void truncated_layer_gives_the_same_light_below(void **state)
{
    (void)state;
    double values[CLOUD_ANGLE_COUNT], cut[CLOUD_ANGLE_COUNT], theta[CLOUD_ANGLE_COUNT];
    double w = stratus_550(values, theta);
    for (int j = 0; j < CLOUD_ANGLE_COUNT; j++)
        cut[j] = values[j];
    double f = cloud_truncate_peak(cut, theta, CLOUD_ANGLE_COUNT);
    print_message("stratus 550 nm: albedo %.6f, peak fraction within 3 degrees %.4f\n", w, f);
    assert_true(f > 0.3 && f < 0.45);
    phase_function full, truncated;
    tabulate(&full, values, theta);
    tabulate(&truncated, cut, theta);
    const double mu[6] = {0.15, 0.3, 0.5, 0.7, 0.85, 1.0};
    const double taus[2] = {30.0, 100.0}, suns[2] = {30.0, 60.0};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            double mu0 = sin(suns[j] * FM_DEG);
            ad_solution a = solve(taus[i], w, mu0, &full, 6, mu);
            ad_solution b = solve(taus[i] * (1.0 - f * w), w * (1.0 - f) / (1.0 - f * w), mu0, &truncated, 6, mu);
            /* the truncated layer's unscattered beam holds the light scattered into the peak: nil here */
            assert_true(b.flux_down_direct < 1e-6);
            double ea = a.flux_down_diffuse + a.flux_down_direct, eb = b.flux_down_diffuse + b.flux_down_direct;
            double worst = 0.0;
            for (int k = 0; k < 6; k++)
                for (int az = 0; az <= 180; az += 45) {
                    double la = ad_radiance_bottom(&a, k, az * FM_DEG), lb = ad_radiance_bottom(&b, k, az * FM_DEG);
                    worst = fmax(worst, fabs(lb / la - 1.0));
                }
            print_message("tau %3.0f, sun %2.0f: ground irradiance %.6f vs %.6f (%+.2e), radiances below within %.2e\n",
                          taus[i], suns[j], ea, eb, eb / ea - 1.0, worst);
            check_rel(eb, ea, 1e-3, "ground irradiance under the truncated layer");
            assert_true(worst < 1e-3);
            ad_free(&a);
            ad_free(&b);
        }
    phase_free(&full);
    phase_free(&truncated);
}

static void truncation_conserves_light_and_moves_g_as_delta_m(void **state)
{
    (void)state;
    double values[CLOUD_ANGLE_COUNT], cut[CLOUD_ANGLE_COUNT], theta[CLOUD_ANGLE_COUNT];
    stratus_550(values, theta);
    for (int j = 0; j < CLOUD_ANGLE_COUNT; j++)
        cut[j] = values[j];
    double f = cloud_truncate_peak(cut, theta, CLOUD_ANGLE_COUNT);
    phase_function full, truncated;
    tabulate(&full, values, theta);
    tabulate(&truncated, cut, theta);
    /* the peak's own mean cosine from g = f <cos> + (1 - f) g' */
    double g = phase_asymmetry(&full, 0), g_cut = phase_asymmetry(&truncated, 0);
    double cos_peak = (g - (1.0 - f) * g_cut) / f;
    print_message("g %.5f, truncated g' %.5f, f %.4f: the peak's mean cosine %.6f\n", g, g_cut, f, cos_peak);
    assert_true(cos_peak > cos(3.0 * FM_DEG) && cos_peak <= 1.0 + 1e-9); /* the peak lies within the cut */
    for (int j = 0; theta[j] >= 3.0 * FM_DEG && j < CLOUD_ANGLE_COUNT; j++)
        assert_true(cut[j] == values[j]); /* beyond the cut nothing moves */
    phase_free(&full);
    phase_free(&truncated);
}

static fm_sky *cloud_sky(double tau)
{
    fm_sky_params p = fm_sky_params_default();
    p.biome = "none";
    p.wavelength_nm = 550.0;
    p.clouds = tau > 0.0 ? "stratus" : NULL;
    p.cloud_tau550 = tau;
    fm_sky *sky;
    fm_error err;
    if (fm_sky_create(&p, &sky, &err))
        fail_msg("%s", err.message);
    return sky;
}

static void only_decks_get_a_truncated_copy(void **state)
{
    (void)state;
    fm_sky *deck = cloud_sky(30.0), *thin = cloud_sky(10.0), *clear = cloud_sky(0.0);
    assert_non_null(deck->truncated);
    assert_null(thin->truncated);
    assert_null(clear->truncated);
    const int c = deck->atm.scattering_count - 1; /* the cloud: the last species added */
    double values[CLOUD_ANGLE_COUNT], theta[CLOUD_ANGLE_COUNT];
    stratus_550(values, theta);
    double f = cloud_truncate_peak(values, theta, CLOUD_ANGLE_COUNT);
    check_rel(deck->truncated->atm.species[c].sigma_s[0], (1.0 - f) * deck->atm.species[c].sigma_s[0], 1e-12,
              "the copy's cloud scattering coefficient");
    fm_sky_destroy(deck);
    fm_sky_destroy(thin);
    fm_sky_destroy(clear);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(truncated_layer_gives_the_same_light_below),
        cmocka_unit_test(truncation_conserves_light_and_moves_g_as_delta_m),
        cmocka_unit_test(only_decks_get_a_truncated_copy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Cloud optics (aerosol/cloud.h) against independent numbers:
 *  - OPAC's own Mie results for its water clouds (tests/data/opac_cloud_optdat.csv: Hess, Koepke &
 *    Schult 1998): extinction per droplet within 1 %, asymmetry parameter within 1.5 %;
 *  - the extinction efficiency of a large sphere tends to 2 (the extinction paradox), with van de
 *    Hulst's edge correction Q - 2 ~ 2 x^(-2/3);
 *  - g of water droplets with r_eff 7-11 um at 550 nm in 0.85-0.875 (Hansen & Travis 1974, fig. 12;
 *    OPAC 0.865-0.867);
 *  - tau from a liquid water path = 3 LWP / (2 rho_w r_eff) times <Q_ext> / 2 (Q_ext 2.0-2.12 at
 *    these size parameters);
 *  - a layer's optical depth at 550 nm is what was asked for, on the profile the estimators see
 *    (fog: 3.912 / V times the thickness);
 *  - the phase table resolves the diffraction peak: its cumulative distribution (which sampling
 *    inverts exactly) matches a dense direct Mie integration within the peak at 400 nm;
 *  - the ice phase function integrates to 1 with g = 0.77. */
#include "check.h"

#include "aerosol/cloud_layer.h"
#include "aerosol/ice_halo.h"
#include "aerosol/mie.h"
#include "base/units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const cloud_type *type_for_code(const char *code)
{
    return cloud_type_find(strcmp(code, "stco") == 0 ? "stratus" : strcmp(code, "stma") == 0 ? "stratocumulus" : "fog");
}

static void optics_match_opac(void **state)
{
    (void)state;
    FILE *f = fopen(FM_TEST_DATA_DIR "/opac_cloud_optdat.csv", "r");
    assert_non_null(f);
    char line[256];
    int rows = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || strncmp(line, "component", 9) == 0)
            continue;
        char code[8];
        double nm, ext, ssa, g;
        assert_int_equal(sscanf(line, "%7[^,],%lf,%lf,%lf,%lf", code, &nm, &ext, &ssa, &g), 5);
        const cloud_type *t = type_for_code(code);
        assert_non_null(t);
        mie_lognormal_result r;
        fm_error err;
        assert_int_equal(cloud_water_optics(t, nm, &r, NULL, &err), FM_OK);
        print_message("%s %3.0f nm: ext %.4e (OPAC %.4e)  1-ssa %.2e (%.2e)  g %.4f (%.3f)\n", code, nm, r.ext_m2, ext,
                      1.0 - r.sca_m2 / r.ext_m2, 1.0 - ssa, r.g, g);
        char what[64];
        snprintf(what, sizeof what, "%s %.0f nm extinction", code, nm);
        check_rel(r.ext_m2, ext, 0.01, what);
        snprintf(what, sizeof what, "%s %.0f nm asymmetry", code, nm);
        check_rel(r.g, g, 0.015, what);
        snprintf(what, sizeof what, "%s %.0f nm single-scattering albedo", code, nm);
        check_abs(r.sca_m2 / r.ext_m2, ssa, 3e-4, what); /* OPAC's four digits: sca / ext to ~2e-4 */
        rows++;
    }
    fclose(f);
    assert_int_equal(rows, 9);
}

/* The 550 nm phase function against OPAC's at every angle it tabulates (0-180 degrees). */
static void phase_matches_opac(void **state)
{
    (void)state;
    FILE *f = fopen(FM_TEST_DATA_DIR "/opac_cloud_phase550.csv", "r");
    assert_non_null(f);
    char line[256], code[8];
    double angle[400], value[400];
    int n = 0;
    const char *codes[] = {"stco", "stma", "fogr"};
    for (int c = 0; c < 3; c++) {
        rewind(f);
        n = 0;
        while (fgets(line, sizeof line, f) && n < 400) {
            if (line[0] != '#' && strncmp(line, "component", 9) != 0 &&
                sscanf(line, "%7[^,],%lf,%lf", code, &angle[n], &value[n]) == 3 && strcmp(code, codes[c]) == 0)
                n++;
        }
        assert_true(n > 100);
        double mu[400], p[400];
        for (int j = 0; j < n; j++)
            mu[j] = cos(angle[j] * FM_DEG);
        mie_lognormal_result r;
        const cloud_type *t = type_for_code(codes[c]);
        assert_int_equal(mie_modified_gamma(&t->size, 0.55, 1.333 - 1.96e-9 * I, NULL, n, mu, p, &r), 0);
        /* within 20 degrees (the diffraction peak) point by point; beyond, OPAC's own values ripple by
         * +-10 % from angle to angle (its coarser size quadrature), so compare sums over 60-180 degrees */
        double worst = 0.0, worst_at = 0.0, ours = 0.0, theirs = 0.0;
        for (int j = 0; j < n; j++) {
            double dev = p[j] / value[j] - 1.0;
            if (getenv("CLOUD_VERBOSE"))
                print_message("  %s %6.1f %.4e %.4e %+.1f%%\n", codes[c], angle[j], p[j], value[j], 100 * dev);
            if (angle[j] <= 20.0 && fabs(dev) > fabs(worst)) {
                worst = dev;
                worst_at = angle[j];
            }
            if (angle[j] >= 60.0) {
                ours += p[j];
                theirs += value[j];
            }
        }
        print_message("%s 550 nm phase: p(0) = %.1f (OPAC %.1f), worst deviation within 20 deg %+.2f%% at %g deg, "
                      "sum over 60-180 deg %+.2f%%\n",
                      codes[c], p[0], value[0], 100 * worst, worst_at, 100 * (ours / theirs - 1.0));
        check_rel(p[0], value[0], 0.01, "forward peak p(0) vs OPAC");
        assert_true(fabs(worst) < 0.025);
        check_rel(ours, theirs, 0.07, "side and backward scattering vs OPAC");
    }
    fclose(f);
}

static void extinction_efficiency_tends_to_two(void **state)
{
    (void)state;
    const double x[] = {300.0, 1000.0, 3000.0, 10000.0};
    for (int i = 0; i < 4; i++) {
        /* averaged over a step of the ripple's period */
        double q = 0.0;
        const int n = 16;
        for (int j = 0; j < n; j++) {
            mie_result r;
            assert_int_equal(mie_sphere(x[i] * (1.0 + 0.01 * j / n), 1.333 - 1e-9 * I, 0, NULL, NULL, NULL, &r), 0);
            q += r.q_ext / n;
        }
        double edge = 2.0 * pow(x[i], -2.0 / 3.0);
        print_message("x = %6.0f: <Q_ext> = %.5f, 2 + 2 x^(-2/3) = %.5f\n", x[i], q, 2.0 + edge);
        char what[64];
        snprintf(what, sizeof what, "Q_ext - 2 at x = %g", x[i]);
        check_rel(q - 2.0, edge, 0.35, what);
    }
}

static void droplet_asymmetry_at_550(void **state)
{
    (void)state;
    for (const cloud_type *t = cloud_types; t->name; t++) {
        if (t->ice)
            continue;
        mie_lognormal_result r;
        fm_error err;
        assert_int_equal(cloud_water_optics(t, 550.0, &r, NULL, &err), FM_OK);
        double reff = modified_gamma_effective_radius_um(&t->size);
        print_message("%-14s r_eff %5.2f um: g(550) = %.4f\n", t->name, reff, r.g);
        assert_true(reff > 7.0 && reff < 12.0);
        assert_true(r.g > 0.85 && r.g < 0.875);
    }
}

static void optical_depth_from_liquid_water_path(void **state)
{
    (void)state;
    for (const cloud_type *t = cloud_types; t->name; t++) {
        fm_error err;
        double tau;
        if (t->ice) {
            assert_int_equal(cloud_tau_from_lwp(t, 100.0, &tau, &err), FM_ERR_INVALID_ARGUMENT);
            continue;
        }
        assert_int_equal(cloud_tau_from_lwp(t, 100.0, &tau, &err), FM_OK);
        double reff_m = modified_gamma_effective_radius_um(&t->size) * 1e-6;
        double formula = 3.0 * 0.1 / (2.0 * CLOUD_WATER_DENSITY * reff_m);
        print_message("%-14s LWP 100 g/m^2: tau = %.3f, 3 LWP / (2 rho r_eff) = %.3f (ratio %.4f)\n", t->name, tau,
                      formula, tau / formula);
        assert_true(tau / formula > 1.0 && tau / formula < 1.06);
    }
}

/* Vertical optical depth at 550 nm of the last species: its cross section times its column. */
static double species_tau(const atmosphere *atm)
{
    const species *sp = &atm->species[atm->species_count - 1];
    return (sp->sigma_s[0] + sp->sigma_a[0]) * profile_column(&sp->profile);
}

static void layer_optical_depth_and_fog_visibility(void **state)
{
    (void)state;
    spectral_grid grid;
    spectral_grid_single(&grid, 550.0);
    fm_error err;
    atmosphere atm;
    assert_int_equal(atmosphere_init_clear_sky(&atm, &grid, 0.0, OZONE_PROFILE_US_STANDARD, 0.2, &err), FM_OK);
    assert_int_equal(cloud_add_layer(&atm, cloud_type_find("stratus"), 520.0, 730.0, 25.0, 1, NULL, 0, &err), FM_OK);
    check_rel(species_tau(&atm), 25.0, 1e-12, "stratus layer's optical depth");
    /* fog of visibility 150 m, 100 m deep: beta = 3.912 / 150 m inside the layer */
    const double visibility = 150.0, depth = 100.0;
    assert_int_equal(
        cloud_add_layer(&atm, cloud_type_find("fog"), 0.0, depth, CLOUD_KOSCHMIEDER / visibility * depth, 1, NULL, 0, &err),
        FM_OK);
    const species *fog = &atm.species[atm.species_count - 1];
    double beta_ground = (fog->sigma_s[0] + fog->sigma_a[0]) * profile_density(&fog->profile, 0.0);
    check_rel(beta_ground * visibility, 3.912, 1e-9, "fog: extinction times visibility at the ground");
    check_rel(species_tau(&atm), 3.912 / visibility * depth, 1e-12, "fog layer's optical depth");
    assert_int_equal(cloud_add_layer(&atm, cloud_type_find("fog"), 0.0, 1e6, 1.0, 1, NULL, 0, &err), FM_ERR_INVALID_ARGUMENT);
    atmosphere_free(&atm);
}

/* Fraction of scattered light within theta of forward, by dense direct integration of the Mie
 * phase function (1e-4 degree steps near the peak). */
static double direct_cone_fraction(const cloud_type *t, double lambda_nm, double theta_max)
{
    const int n = 4000;
    double *mu = malloc(sizeof(double) * (n + 1)), *p = malloc(sizeof(double) * (n + 1)), *th = malloc(sizeof(double) * (n + 1));
    for (int i = 0; i <= n; i++) {
        double s = (double)i / n;
        th[i] = theta_max * s * s;
        mu[i] = cos(th[i]);
    }
    mie_lognormal_result r;
    modified_gamma_size size = t->size;
    double complex m = 1.339 - 1.86e-9 * I; /* water at 400 nm */
    assert_int_equal(mie_modified_gamma(&size, lambda_nm * 1e-3, m, NULL, n + 1, mu, p, &r), 0);
    double sum = 0.0;
    for (int i = 0; i < n; i++)
        sum += 0.5 * (p[i] * sin(th[i]) + p[i + 1] * sin(th[i + 1])) * (th[i + 1] - th[i]);
    free(mu);
    free(p);
    free(th);
    return 2.0 * FM_PI * sum;
}

static void phase_table_resolves_the_diffraction_peak(void **state)
{
    (void)state;
    spectral_grid grid;
    spectral_grid_single(&grid, 400.0);
    fm_error err;
    atmosphere atm;
    assert_int_equal(atmosphere_init_clear_sky(&atm, &grid, 0.0, OZONE_PROFILE_US_STANDARD, 0.2, &err), FM_OK);
    const cloud_type *t = cloud_type_find("stratocumulus"); /* the larger droplets: the narrower peak */
    assert_int_equal(cloud_add_layer(&atm, t, 1000.0, 500.0, 10.0, 1, NULL, 0, &err), FM_OK);
    const phase_function *p = &atm.species[atm.species_count - 1].phase;
    assert_int_equal(p->kind, PHASE_TABULATED);
    const int nodes[] = {8, 15, 30, 60, 120};
    for (int i = 0; i < 5; i++) {
        int j = nodes[i];
        double theta = cloud_angle_rad(j);
        double table = p->table->cdf[j]; /* P(cos_theta >= mu_j) (phase/phase_table.h) */
        double direct = direct_cone_fraction(t, 400.0, theta);
        print_message("within %6.3f deg: table %.5f, direct Mie %.5f\n", theta / FM_DEG, table, direct);
        char what[64];
        snprintf(what, sizeof what, "fraction scattered within %.3f deg", theta / FM_DEG);
        check_abs(table, direct, 1e-3, what);
    }
    /* sampling draws exactly the table's distribution: the fraction of 2e5 draws inside node 15 */
    int inside = 0;
    const int draws = 200000;
    double mu15 = cos(cloud_angle_rad(15));
    for (int i = 0; i < draws; i++)
        inside += phase_sample(p, 0, (i + 0.5) / draws) >= mu15;
    check_abs((double)inside / draws, p->table->cdf[15], 2.0 / draws, "sampled fraction within node 15");
    atmosphere_free(&atm);
}

/* The sun's chord through a layer (the sidecar's transmittance): from below, inside and above a
 * layer near the ground, where the shell is a plane slab but for the curvature (6e-4 for a layer
 * 1 km up and the sun 30 degrees up, 3e-5 within 200 m of the ground). */
static void chord_through_a_layer(void **state)
{
    (void)state;
    const double R = 6371e3, mu = 0.5;
    check_rel(cloud_shell_chord_m(R, mu, R + 1000.0, R + 1500.0), 500.0 / mu, 1e-3, "below: thickness / mu");
    check_rel(cloud_shell_chord_m(R + 50.0, mu, R, R + 200.0), 150.0 / mu, 1e-4, "inside fog: to its top / mu");
    check_abs(cloud_shell_chord_m(R + 2000.0, mu, R + 1000.0, R + 1500.0), 0.0, 0.0, "above: nothing");
    check_rel(cloud_shell_chord_m(R, 1.0, R + 1000.0, R + 1500.0), 500.0, 1e-12, "overhead: the thickness");
}

static void ice_phase_function(void **state)
{
    (void)state;
    double norm = 0.0, mean = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; i++) {
        double mu = -1.0 + 2.0 * (i + 0.5) / n, p = cloud_ice_phase(mu);
        norm += 2.0 * FM_PI * p * 2.0 / n;
        mean += 2.0 * FM_PI * p * mu * 2.0 / n;
    }
    check_rel(norm, 1.0, 1e-4, "ice phase function's integral");
    check_rel(mean, cloud_ice_asymmetry(), 1e-3, "ice asymmetry parameter");
    print_message("ice g %.4f\n", cloud_ice_asymmetry());
    assert_true(cloud_ice_asymmetry() > 0.74 && cloud_ice_asymmetry() < 0.80); /* Baum 2005, Garrett 2003 */
}

/* The 22-degree halo: nothing inside the minimum deviation of a 60-degree ice prism (21.96 degrees for
 * n = 1.3116), its brightest just outside it (the caustic of minimum deviation), and in the whole
 * ice phase function a ring brighter than the sky inside it although the lobes fall with angle. */
static void ice_halo_at_minimum_deviation(void **state)
{
    (void)state;
    double d_min = ice_halo_minimum_deviation(ICE_REFRACTIVE_INDEX) / FM_DEG;
    check_abs(d_min, 21.96, 0.01, "minimum deviation of a 60-degree ice prism (degrees)");
    double peak = 0.0, at = 0.0, inside = 0.0;
    for (double t = 10.0; t < 60.0; t += 0.05) {
        double p = ice_halo_phase(cos(t * FM_DEG));
        if (t < d_min - 0.1)
            inside = fmax(inside, p);
        if (p > peak) {
            peak = p;
            at = t;
        }
    }
    check_abs(inside, 0.0, 0.0, "halo inside the minimum deviation");
    print_message("halo brightest at %.2f degrees (minimum deviation %.2f)\n", at, d_min);
    check_abs(at, d_min + 0.3, 0.4, "halo's brightest angle (degrees)");
    double sky = cloud_ice_phase(cos((d_min - 1.0) * FM_DEG)), ring = cloud_ice_phase(cos((d_min + 0.5) * FM_DEG));
    print_message("ice phase function: %.4f at %.1f degrees, %.4f at %.1f\n", sky, d_min - 1.0, ring, d_min + 0.5);
    assert_true(ring > 1.2 * sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(optics_match_opac),
        cmocka_unit_test(phase_matches_opac),
        cmocka_unit_test(extinction_efficiency_tends_to_two),
        cmocka_unit_test(droplet_asymmetry_at_550),
        cmocka_unit_test(optical_depth_from_liquid_water_path),
        cmocka_unit_test(layer_optical_depth_and_fog_visibility),
        cmocka_unit_test(phase_table_resolves_the_diffraction_peak),
        cmocka_unit_test(chord_through_a_layer),
        cmocka_unit_test(ice_phase_function),
        cmocka_unit_test(ice_halo_at_minimum_deviation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

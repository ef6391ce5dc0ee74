/* Optical depth along rays: ray geometry, the closed form against an independent fine quadrature,
 * the fast quadrature and the tables against the closed form. */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/rng.h"
#include "base/units.h"
#include "transport/free_flight.h"

#include <math.h>
#include <string.h>

static fm_sky *sky;

static int setup(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    fm_error err;
    return fm_sky_create(&p, &sky, &err) == FM_OK ? 0 : -1;
}

static int teardown(void **state)
{
    fm_sky_destroy(sky);
    return 0;
}

static void ray_geometry(void **state)
{
    const atmosphere *a = &sky->atm;
    double R = a->bottom_radius_m, H = FM_ATMOSPHERE_HEIGHT_M;
    check_rel(ray_distance_to_top(a, R, 1.0), H, 1e-12, "vertical distance to the top");
    check_rel(ray_distance_to_top(a, R, 0.0), sqrt((R + H) * (R + H) - R * R), 1e-12, "horizontal");
    assert_false(ray_hits_ground(a, R, 0.0));
    assert_true(ray_hits_ground(a, R + 1000.0, -0.5));
    /* from 10 km, the horizon is at mu = -sqrt(1 - (R/r)^2) */
    double r = R + 10000.0, mh = horizon_mu(a, r);
    assert_true(ray_hits_ground(a, r, mh - 1e-6));
    assert_false(ray_hits_ground(a, r, mh + 1e-6));
    check_rel(ray_distance_to_ground(a, r, -1.0), 10000.0, 1e-9, "straight down");
    /* from the ground itself every downward ray ends where it starts: exactly 0, not a rounding
     * error's sliver of air (an observer on the ground, the table's downward nodes) */
    for (double mu = -0.9999; mu < 0.0; mu += 0.0137)
        assert_true(ray_distance_to_ground(a, R, mu) == 0.0);
    /* 1 m up, the nearer root in long double: (r^2 - R^2) / (-r mu + sqrt(disc)) is the same root */
    for (double mu = -1.0; mu < -0.01; mu += 0.0731) {
        long double rl = (long double)R + 1.0L, disc = rl * rl * ((long double)mu * mu - 1.0L) + (long double)R * R;
        double expected = (double)(-rl * mu - sqrtl(disc));
        check_rel(ray_distance_to_ground(a, R + 1.0, mu), expected, 1e-6, "1 m up");
    }
}

/* Independent check: Simpson's rule with many points on the density evaluated pointwise. */
static double simpson_column(const atmosphere *a, int c, double r, double mu, double t_max, int n)
{
    double h = t_max / n, sum = 0.0;
    for (int i = 0; i <= n; i++) {
        double t = i * h;
        double rr = sqrt(r * r + t * t + 2.0 * r * mu * t);
        double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += w * profile_density(&a->species[c].profile, rr - a->bottom_radius_m);
    }
    return sum * h / 3.0;
}

static void closed_form_matches_fine_quadrature(void **state)
{
    const atmosphere *a = &sky->atm;
    const double R = a->bottom_radius_m;
    const double cases[][2] = {{0, 1}, {0, 0.3}, {0, 0.0}, {2000, -0.01}, {15000, -0.05}, {40000, 0.7}};
    for (int i = 0; i < 6; i++) {
        double r = R + cases[i][0], mu = cases[i][1];
        double t = ray_distance_to_boundary(a, r, mu, NULL);
        double exact[FM_MAX_SPECIES], quad[FM_MAX_SPECIES];
        column_exact(a, r, mu, t, exact);
        column_quadrature(a, r, mu, t, quad);
        for (int c = 0; c < a->species_count; c++) {
            double simpson = simpson_column(a, c, r, mu, t, 400000);
            check_rel(exact[c], simpson, 2e-6, "closed form vs Simpson");
            check_rel(quad[c], exact[c], 5e-5, "Gauss-Legendre pieces vs closed form");
        }
    }
}

/* Aerosol layers end in 50 m ramps; a Gauss piece with a ramp's end inside misses the kink.  Rays
 * grazing the stratospheric layer's top (35 km, between the fixed breakpoints at 33 and 36 km)
 * and the boundary layer's (2 km), each species' column against the closed form.  Before the
 * layers' kinks were breakpoints, the first ray's stratospheric column was 0.76% off. */
static void quadrature_breaks_at_layer_edges(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    p.biome = "urban";
    p.turbidity = 2.0;
    fm_sky *urban;
    fm_error err;
    assert_int_equal(fm_sky_create(&p, &urban, &err), FM_OK);
    const atmosphere *a = &urban->atm;
    const double cases[][2] = {{37904.0, -0.03259}, {35052.0, -0.0118}, {40000.0, -0.0345}, {2500.0, -0.012},
                               {2040.0, -0.0011}, {36000.0, 0.02}};
    for (int i = 0; i < 6; i++) {
        double r = a->bottom_radius_m + cases[i][0], mu = cases[i][1];
        double t = ray_distance_to_top(a, r, mu), exact[FM_MAX_SPECIES], quad[FM_MAX_SPECIES];
        column_exact(a, r, mu, t, exact);
        column_quadrature(a, r, mu, t, quad);
        for (int c = 0; c < a->species_count; c++)
            if (strcmp(a->species[c].name, "aerosol") == 0 && exact[c] > 0.0)
                check_rel(quad[c], exact[c], 1e-6, "aerosol column across a layer's edge");
    }
    fm_sky_destroy(urban);
}

/* The transmittance tables are used for sunlight; check optical depth where it matters. */
static void column_table_accuracy(void **state)
{
    const atmosphere *a = &sky->atm;
    rng r = rng_for(1, 2, 3);
    double worst = 0.0;
    for (int i = 0; i < 3000; i++) {
        double z = 100000.0 * pow(rng_uniform(&r), 2.0), rr = a->bottom_radius_m + z;
        double mh = horizon_mu(a, rr), mu = mh + (1.0 - mh) * pow(rng_uniform(&r), 2.0);
        double tab[FM_MAX_SPECIES], exact[FM_MAX_SPECIES];
        if (!column_table_lookup(&sky->columns, a, rr, mu, tab))
            continue;
        column_exact(a, rr, mu, ray_distance_to_top(a, rr, mu), exact);
        double tau_exact = atmosphere_optical_depth(a, exact, 0); /* 380 nm: the thickest */
        double tau_tab = atmosphere_optical_depth(a, tab, 0);
        double err = fabs(tau_tab - tau_exact) / fmax(1.0, tau_exact); /* absolute below 1, relative above */
        worst = fmax(worst, err);
    }
    check_abs(worst, 0.0, 2e-3, "column table: worst optical-depth error at 380 nm");
}

static void sun_table_accuracy(void **state)
{
    const atmosphere *a = &sky->atm;
    rng r = rng_for(4, 5, 6);
    double worst = 0.0, worst_day = 0.0;
    double tab[FM_MAX_WAVELENGTHS], direct[FM_MAX_WAVELENGTHS];
    for (int i = 0; i < 3000; i++) {
        double z = 100000.0 * pow(rng_uniform(&r), 2.0), rr = a->bottom_radius_m + z;
        double mu = -0.2 + 1.2 * pow(rng_uniform(&r), 2.0);
        sun_irradiance_lookup(&sky->sun_table, a, &sky->sun, rr, mu, tab, NULL);
        sun_transmittance_direct(a, &sky->columns, &sky->sun, rr, mu, direct, NULL);
        for (int k = 0; k < a->grid.count; k++) {
            worst = fmax(worst, fabs(tab[k] - direct[k]));
            if (mu > 0.05) /* the sun more than ~3 degrees above the local horizontal */
                worst_day = fmax(worst_day, fabs(tab[k] / direct[k] - 1.0));
        }
    }
    check_abs(worst, 0.0, 6e-3, "sun table: worst absolute transmittance error (twilight included)");
    check_abs(worst_day, 0.0, 1e-3, "sun table: worst relative error with the sun above 3 degrees");
}

/* Delta tracking's majorant bounds the extinction everywhere, for every wavelength. */
static void majorants_bound_the_medium(void **state)
{
    const atmosphere *a = &sky->atm;
    double ss[FM_MAX_WAVELENGTHS], st[FM_MAX_WAVELENGTHS];
    for (double z = 0.0; z < FM_ATMOSPHERE_HEIGHT_M; z += 37.0) {
        double rr = a->bottom_radius_m + z;
        atmosphere_coefficients(a, rr, ss, st);
        int s = atmosphere_shell_of(a, rr);
        for (int k = 0; k < a->grid.count; k++)
            if (st[k] > a->shell_majorant[s][k])
                fail_msg("z=%g k=%d: sigma_t %g > majorant %g", z, k, st[k], a->shell_majorant[s][k]);
    }
}

/* free_flight_majorant_depth sums majorant columns per species and expands them per wavelength at
 * the end (free_flight.c): against the majorant table itself summed along the ray by a fine
 * midpoint rule, every wavelength, rays from 0 to 60 km in every direction. */
static void majorant_depth_sums_the_shells(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    p.biome = "urban";
    p.turbidity = 2.0;
    fm_sky *urban = test_sky(&p);
    rng r = rng_for(11, 12, 13);
    for (int i = 0; i < 40; i++) {
        const atmosphere *a = i % 2 ? &urban->atm : &sky->atm; /* molecules and ozone; and aerosol layers */
        const int K = a->grid.count;
        double z = 60000.0 * rng_uniform(&r), mu = 2.0 * rng_uniform(&r) - 1.0;
        vec3 origin = v3(0.0, 0.0, a->bottom_radius_m + z), dir = v3(sqrt(1.0 - mu * mu), 0.0, mu);
        ray_segment seg;
        ray_segment_init(&seg, a, origin, dir);
        double depth[FM_MAX_WAVELENGTHS], fine[FM_MAX_WAVELENGTHS] = {0};
        free_flight_majorant_depth(a, &seg, 0.0, seg.t_end, depth);
        const int steps = 2000000;
        const double dt = seg.t_end / steps;
        double length[FM_MAX_SHELLS] = {0}; /* m of the ray in each shell, by midpoints */
        for (int j = 0; j < steps; j++)
            length[atmosphere_shell_of(a, ray_segment_radius(&seg, (j + 0.5) * dt))] += dt;
        for (int s = 0; s < a->shell_count; s++)
            for (int k = 0; k < K; k++)
                fine[k] += a->shell_majorant[s][k] * length[s];
        for (int k = 0; k < K; k++)
            check_rel(depth[k], fine[k], 2e-5, "majorant depth against the shells summed finely");
    }
    fm_sky_destroy(urban);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ray_geometry),
        cmocka_unit_test(closed_form_matches_fine_quadrature),
        cmocka_unit_test(quadrature_breaks_at_layer_edges),
        cmocka_unit_test(column_table_accuracy),
        cmocka_unit_test(sun_table_accuracy),
        cmocka_unit_test(majorants_bound_the_medium),
        cmocka_unit_test(majorant_depth_sums_the_shells),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

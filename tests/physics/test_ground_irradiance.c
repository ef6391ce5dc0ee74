/* The ground's diffuse irradiance (transport/ground_irradiance.h): order 1 by quadrature, higher
 * orders by paths.  Checked against the path tracer itself, an independent estimator of the same
 * integral: E_d = pi * mean(L) over cosine-distributed directions from the ground point, with
 * plain pseudo-random streams (no quasi-Monte Carlo, no shared code with the quadrature).
 *  - order 1 alone (max_order 1): the quadrature against 400 000 order-1 paths, in skies where
 *    its grid matters: desert dust (the forward peak), clear air, the urban sunset, twilight -4;
 *  - its grid: 32 x 32 nodes against 64 x 64 (the final quality's against a finer one);
 *  - all orders: the table against 60 000 full paths (rural, sun 30);
 *  - the path tracer's ground bounce: the ground seen from the observer at order 2 against albedo /
 *    pi times the order-1 quadrature (desert dust, where the bounce's sun guide matters; clear air).
 * A quadrature that lost the forward peak, the horizon or a factor of pi, or a decomposition that
 * counted order 1 twice or not at all, misses these by far more than the bounds. */
#include "check.h"

#include "base/rng.h"
#include "base/units.h"
#include "spectrum/spectral_grid.h"
#include "render/render.h"
#include "transport/ground_irradiance_build.h"
#include "transport/twilight.h"

#include <math.h>

static double luminance(const fm_sky *sky, const double *E)
{
    double xyz[3];
    spectral_grid_to_xyz(&sky->atm.grid, E, xyz);
    return xyz[1];
}

static fm_sky *sky_for(const char *biome_name, double sun_deg, double turbidity)
{
    fm_sky_params p = fm_sky_params_default();
    p.biome = biome_name;
    p.sun_elevation_deg = sun_deg;
    p.sun_azimuth_deg = 0.0;
    p.turbidity = turbidity;
    return test_sky(&p);
}

/* The ground quadrature a final map takes (render.c). */
static ground_quadrature final_quadrature(void)
{
    quality_settings q = render_quality_settings(FM_QUALITY_FINAL, 1.0);
    return (ground_quadrature){q.ground_rows, q.ground_cols, q.ss_points};
}

/* The table's E_d (CIE Y) at the observer's ground point. */
static double table_irradiance(const fm_sky *sky, const path_context *pc, ground_quadrature q, int paths)
{
    ground_irradiance g;
    fm_status s = ground_irradiance_build(&g, pc, acos(sky->sun_dir.z), 0.0, q, paths, 3, 2, NULL);
    assert_int_equal(s, FM_OK);
    double y = luminance(sky, g.E);
    ground_irradiance_free(&g);
    return y;
}

/* pi * mean(L) over N cosine-distributed directions from the ground point; *se its standard error. */
static double path_irradiance(const fm_sky *sky, const path_context *pc, int N, double *se)
{
    const int K = sky->atm.grid.count;
    vec3 origin = v3_scale(v3_normalize(sky->observer), sky->atm.bottom_radius_m);
    frame local = frame_from_normal(v3_normalize(origin));
    double s1 = 0.0, s2 = 0.0;
    for (int i = 0; i < N; i++) {
        rng r = rng_for(11, 0x6a09e667ull, (uint64_t)i);
        double u1 = rng_uniform(&r), u2 = rng_uniform(&r), sr = sqrt(u1), phi = 2.0 * FM_PI * u2;
        vec3 d = v3_normalize(frame_to_world(&local, v3(sr * cos(phi), sr * sin(phi), sqrt(1.0 - u1))));
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(pc, origin, d, i % K, &r, L);
        double y = FM_PI * luminance(sky, L);
        s1 += y;
        s2 += y * y;
    }
    double mean = s1 / N;
    *se = sqrt(fmax(s2 / N - mean * mean, 0.0) / N);
    return mean;
}

static void check_order_one(const char *biome_name, double sun_deg, double turbidity)
{
    fm_sky *sky = sky_for(biome_name, sun_deg, turbidity);
    path_context pc = twilight_path_context(sky, NULL, 1, 1);
    double fine = table_irradiance(sky, &pc, (ground_quadrature){64, 64, 6}, 1);
    double final = table_irradiance(sky, &pc, final_quadrature(), 1);
    double se, paths = path_irradiance(sky, &pc, 400000, &se);
    double z = (final - paths) / se;
    print_message("%s sun %g T %g: order-1 E_d quadrature %.6g (64 x 64: %.6g), paths %.6g +- %.2g (z %.2f)\n", biome_name,
                  sun_deg, turbidity, final, fine, paths, se, z);
    check_rel(final, fine, 2e-4, "32 x 32 quadrature against 64 x 64");
    check_abs(z, 0.0, 4.0, "quadrature against order-1 paths (z)");
    fm_sky_destroy(sky);
}

static void order_one_desert_dust(void **state)
{
    (void)state;
    check_order_one("desert-dust", 30.0, 1.0);
}

static void order_one_clear(void **state)
{
    (void)state;
    check_order_one("none", 30.0, 1.0);
}

static void order_one_urban_sunset(void **state)
{
    (void)state;
    check_order_one("urban", 2.0, 2.0);
}

static void order_one_twilight(void **state)
{
    (void)state;
    check_order_one("rural", -4.0, 1.0);
}

/* The ground bounce's directions (path.c: the cosine lobe and, with aerosols, the sun guide by
 * one-sample MIS): the ground seen from the observer, order 2 (a bounce, then one scattering in the
 * air), is albedo / pi times the order-1 diffuse irradiance, which the quadrature gives without any
 * bounce.  Wrong MIS weights, or a guided direction into the ground counted, miss by far more. */
static void check_bounce(const char *biome_name)
{
    fm_sky *sky = sky_for(biome_name, 30.0, 1.0);
    const int K = sky->atm.grid.count, N = 200000;
    path_context single = twilight_path_context(sky, NULL, 1, 1);
    ground_irradiance g;
    assert_int_equal(ground_irradiance_build(&g, &single, acos(sky->sun_dir.z), 0.0, final_quadrature(), 1,
                                             3, 2, NULL),
                     FM_OK);
    double reflected[FM_MAX_WAVELENGTHS];
    for (int k = 0; k < K; k++)
        reflected[k] = sky->atm.ground_albedo[k] / FM_PI * g.E[k];
    double expected = luminance(sky, reflected);
    ground_irradiance_free(&g);
    path_context pc = twilight_path_context(sky, NULL, 2, 2);
    vec3 down = v3_normalize(v3(0.3, 0.2, -1.0));
    double s1 = 0.0, s2 = 0.0;
    for (int i = 0; i < N; i++) {
        rng r = rng_for(13, 0xbb67ae85ull, (uint64_t)i);
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(&pc, sky->observer, down, i % K, &r, L);
        double y = luminance(sky, L);
        s1 += y;
        s2 += y * y;
    }
    double mean = s1 / N, se = sqrt(fmax(s2 / N - mean * mean, 0.0) / N), z = (mean - expected) / se;
    print_message("%s sun 30: the ground's order 2 seen from the observer %.6g +- %.2g, albedo / pi x order-1 E_d "
                  "%.6g (z %.2f; relative sd per path %.2f)\n",
                  biome_name, mean, se, expected, z, se * sqrt(N) / mean);
    check_abs(z, 0.0, 4.0, "a bounce's order 2 against the quadrature (z)");
    fm_sky_destroy(sky);
}

static void bounce_desert_dust(void **state)
{
    (void)state;
    check_bounce("desert-dust");
}

static void bounce_clear(void **state)
{
    (void)state;
    check_bounce("none");
}

static void all_orders_rural(void **state)
{
    (void)state;
    fm_sky *sky = sky_for("rural", 30.0, 1.0);
    path_context pc = twilight_path_context(sky, NULL, 1, 0);
    pc.segment_sunlight = SEGMENT_SUNLIGHT_ALL; /* as the renderer's ground irradiance */
    double table = table_irradiance(sky, &pc, final_quadrature(), 16384);
    double se, paths = path_irradiance(sky, &pc, 60000, &se);
    double z = (table - paths) / se;
    print_message("rural sun 30: all-orders E_d table %.6g, paths %.6g +- %.2g (z %.2f)\n", table, paths, se, z);
    /* the table's own noise (orders >= 2, 16384 paths) is well below the 60 000 full paths' */
    check_abs(z, 0.0, 4.0, "table against all-order paths (z)");
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(order_one_desert_dust),  cmocka_unit_test(order_one_clear),
        cmocka_unit_test(order_one_urban_sunset), cmocka_unit_test(order_one_twilight),
        cmocka_unit_test(all_orders_rural),       cmocka_unit_test(bounce_desert_dust),
        cmocka_unit_test(bounce_clear),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

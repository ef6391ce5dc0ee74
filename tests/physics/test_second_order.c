/* Second-order scattering: the path tracer restricted to exactly two scattering events against a
 * deterministic quadrature of
 *     L2(x0, d) = integral_0^t_end T(0, t) sigma_s(x_t) integral_4pi p(d' . d) L1(x_t, d') dOmega' dt,
 * ground albedo 0 so that only air scatters.  The inner L1 is the single-scattering quadrature that
 * test_single_scattering checks against an independent reference; the outer integrals are Simpson
 * along the ray and Gauss-Legendre x trapezoid over the sphere, split at the local horizon.
 * A path tracer that sampled directions uniformly without the phase weight, or that weighted any
 * vertex wrongly, misses these values by several percent.
 *
 * The fast path's table parts each node's light into order 2 and the orders above, from the same
 * paths (render.c fits them apart): order 2 must be what the paths cut at order 2 give, the rest
 * what they give from order 3 on, and the two the whole; and the aerosols' aureole, which the part
 * rests on, must be order 2's.  Order 2 is fitted divided by an approximation without noise
 * (next_order_shape.h), which must carry that aureole: order 2 over it within 0.6-1.2 and smooth
 * along the row through the sun. */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/quadrature.h"
#include "base/rng.h"
#include "base/units.h"
#include "phase/phase_rayleigh.h"
#include "spectrum/spectral_grid.h"
#include "transport/single_scatter.h"
#include "transport/next_order_shape.h"
#include "transport/sky_path.h"
#include "transport/twilight.h"

#include <math.h>

/* Integral over the sphere of p(d' . d) L1(y, d') around the point y. */
static double in_scattered(const fm_sky *sky, const path_context *one, vec3 y, vec3 d)
{
    const atmosphere *a = &sky->atm;
    double gamma = a->species[0].phase.param[0];
    double r = v3_length(y);
    frame f = frame_from_normal(v3_scale(y, 1.0 / r));
    double mh = horizon_mu(a, r);
    const double bounds[4] = {-1.0, mh, fmin(mh + 0.15, 1.0), 1.0};
    const int points[3] = {10, 12, 14};
    const int n_phi = 24;
    double sum = 0.0;
    for (int part = 0; part < 3; part++) {
        const gauss_rule *g = gauss_legendre_cached(points[part]);
        double half = 0.5 * (bounds[part + 1] - bounds[part]), mid = 0.5 * (bounds[part + 1] + bounds[part]);
        for (int i = 0; i < g->n; i++) {
            double mu = mid + half * g->x[i], s = sqrt(fmax(0.0, 1.0 - mu * mu));
            for (int j = 0; j < n_phi; j++) {
                double phi = 2.0 * FM_PI * (j + 0.5) / n_phi;
                vec3 dp = frame_to_world(&f, v3(s * cos(phi), s * sin(phi), mu));
                double L1[1] = {0};
                single_scatter_radiance(one, y, dp, L1);
                sum += half * g->w[i] * (2.0 * FM_PI / n_phi) * phase_rayleigh_eval(v3_dot(dp, d), gamma) * L1[0];
            }
        }
    }
    return sum;
}

typedef struct source_ctx {
    const fm_sky *sky;
    const path_context *one;
    vec3 d;
} source_ctx;

/* Order-2 source along the view ray: sigma_s(x) times the in-scattered order-1 radiance. */
static double second_order_source(void *p, vec3 x)
{
    const source_ctx *c = p;
    return test_molecular_scattering(c->sky, x) * in_scattered(c->sky, c->one, x, c->d);
}

static double second_order_quadrature(const fm_sky *sky, vec3 d, int steps)
{
    path_context one = sky_path_context(sky, 1, 1);
    source_ctx ctx = {sky, &one, d};
    return test_view_ray_integral(sky, d, steps, second_order_source, &ctx, NULL, NULL);
}

static void second_order_matches_quadrature(void **state)
{
    fm_sky_params p = test_params(30.0, 450.0);
    p.sun_azimuth_deg = 180.0;
    p.ground_albedo = 0.0;
    fm_sky *sky = test_sky(&p);
    const double dirs[3][2] = {{90, 0}, {20, 180}, {5, 0}};
    path_context two = sky_path_context(sky, 2, 2);
    for (int i = 0; i < 3; i++) {
        vec3 d = direction_from_elevation_azimuth(dirs[i][0] * FM_DEG, dirs[i][1] * FM_DEG);
        double ref = second_order_quadrature(sky, d, 40);
        double se, mean = test_path_radiance(&two, sky->observer, d, 4000000, 99, (uint64_t)i, &se);
        print_message("direction (%g, %g): quadrature %.6e, path tracer %.6e +- %.1e\n", dirs[i][0], dirs[i][1], ref,
                      mean, se);
        assert_true(se < 2.5e-3 * ref);
        check_rel(mean, ref, 1e-2, "second-order radiance: path tracer vs quadrature");
    }
    fm_sky_destroy(sky);
}

/* The table's paths (render.c's ms_nodes: orders >= 2, first vertices along the view ray, the
 * ground seen directly left to single scattering) for desert dust, the sun 30 degrees up in the
 * south; in colour, or at the one wavelength lambda_nm if it is positive. */
static fm_sky *desert_dust_sky(path_context *pc, int min_order, int max_order, double lambda_nm)
{
    fm_sky_params p = test_params(30.0, lambda_nm);
    p.sun_azimuth_deg = 180.0;
    p.biome = "desert-dust";
    fm_sky *sky = test_sky(&p);
    *pc = twilight_path_context(sky, NULL, min_order, max_order);
    pc->skip_ground_first = 1;
    return sky;
}

static void table_orders_part_the_same_paths(void **state)
{
    path_context pc, cut, later_only;
    fm_sky *sky = desert_dust_sky(&pc, 2, 0, 0.0);
    cut = later_only = pc;
    cut.max_order = 2;
    later_only.min_order = 3;
    const int K = sky->atm.grid.count, N = 2000;
    const double dirs[3][2] = {{30, 175}, {60, 90}, {5, 0}}; /* near the sun, the side, the north horizon */
    for (int i = 0; i < 3; i++) {
        vec3 d = direction_from_elevation_azimuth(dirs[i][0] * FM_DEG, dirs[i][1] * FM_DEG);
        double whole[FM_MAX_WAVELENGTHS] = {0}, parted[FM_MAX_WAVELENGTHS] = {0}, later[FM_MAX_WAVELENGTHS] = {0};
        double two[FM_MAX_WAVELENGTHS] = {0}, three[FM_MAX_WAVELENGTHS] = {0};
        node_orders orders = {later, {0.0, 0.0}};
        table_node_paths(sky, &pc, d, N, 5, (uint64_t)i, 0, whole, NULL, NULL, NULL);
        table_node_paths(sky, &pc, d, N, 5, (uint64_t)i, 0, parted, NULL, NULL, &orders);
        table_node_paths(sky, &cut, d, N, 5, (uint64_t)i, 0, two, NULL, NULL, NULL);
        table_node_paths(sky, &later_only, d, N, 5, (uint64_t)i, 0, three, NULL, NULL, NULL);
        double y = spectral_grid_luminance(&sky->atm.grid, whole);
        double y3 = spectral_grid_luminance(&sky->atm.grid, later);
        print_message("elevation %2.0f azimuth %3.0f: orders >= 3 %.1f%% of the table's light\n", dirs[i][0],
                      dirs[i][1], 100.0 * y3 / y);
        assert_true(y3 > 0.1 * y && y3 < 0.9 * y);
        double off[3] = {0.0, 0.0, 0.0}; /* the largest differences over the wavelengths, relative to the whole */
        for (int k = 0; k < K; k++) {
            off[0] = fmax(off[0], fabs(parted[k] - whole[k]) / whole[k]);
            off[1] = fmax(off[1], fabs(parted[k] - later[k] - two[k]) / whole[k]);
            off[2] = fmax(off[2], fabs(later[k] - three[k]) / whole[k]);
        }
        check_abs(off[0], 0.0, 1e-12, "the parted node's whole against the node's");
        check_abs(off[1], 0.0, 1e-12, "order 2 against the paths cut at order 2");
        check_abs(off[2], 0.0, 1e-12, "orders >= 3 against the paths counted from order 3");
        /* the squared luminances of the parts: each at least the square of its mean (Cauchy-Schwarz) */
        double y2 = spectral_grid_luminance(&sky->atm.grid, two) / N, y3m = y3 / N;
        assert_true(orders.yy[0] / N >= y2 * y2 && orders.yy[1] / N >= y3m * y3m);
    }
    fm_sky_destroy(sky);
}

/* The cosine coefficient m of a row of COLS values over uniform relative azimuths 0..180 degrees,
 * over the row's mean (trapezoid rule, which makes the cosines orthogonal on those columns). */
enum { COLS = 13 };
static double cosine_share(const double *row, int m)
{
    double c[2] = {0.0, 0.0}, norm[2] = {0.0, 0.0};
    for (int j = 0; j < COLS; j++) {
        double t = j == 0 || j == COLS - 1 ? 0.5 : 1.0, cm = cos(FM_PI * m * j / (COLS - 1));
        c[0] += t * row[j];
        norm[0] += t;
        c[1] += t * cm * row[j];
        norm[1] += t * cm * cm;
    }
    return (c[1] / norm[1]) / (c[0] / norm[0]);
}

/* A row of table nodes through the sun (elevation 30, 13 relative azimuths): the 5th cosine of order 2
 * and of the orders above. */
static void aureole_is_order_two(void **state)
{
    path_context pc;
    fm_sky *sky = desert_dust_sky(&pc, 2, 0, 0.0);
    enum { N = 4096, M = 5 };
    double row[2][COLS];
    for (int j = 0; j < COLS; j++) {
        vec3 d = direction_from_elevation_azimuth(30.0 * FM_DEG, (180.0 - 180.0 * j / (COLS - 1)) * FM_DEG);
        double whole[FM_MAX_WAVELENGTHS] = {0}, later[FM_MAX_WAVELENGTHS] = {0};
        node_orders orders = {later, {0.0, 0.0}};
        table_node_paths(sky, &pc, d, N, 9, (uint64_t)(100 + j), 0, whole, NULL, NULL, &orders);
        row[1][j] = spectral_grid_luminance(&sky->atm.grid, later);
        row[0][j] = spectral_grid_luminance(&sky->atm.grid, whole) - row[1][j];
    }
    double share[2] = {cosine_share(row[0], M), cosine_share(row[1], M)};
    print_message("desert dust, sun 30, the row through the sun: cosine %d over the mean %.3f for order 2, %.3f "
                  "for orders >= 3\n",
                  M, share[0], share[1]);
    /* measured 0.29 and 0.03 at 16 times the final table's paths (render.c, fit_table) */
    assert_true(share[0] > 0.15);
    assert_true(fabs(share[1]) < 0.08);
    fm_sky_destroy(sky);
}

/* The observer's single-scattering field at the sky's one wavelength (next_order_shape.h). */
static double observer_single_scatter(void *ctx, vec3 d)
{
    const fm_sky *sky = ctx;
    path_context one = sky_path_context(sky, 1, 1);
    double L[1] = {0.0};
    single_scatter_radiance(&one, sky->observer, d, L);
    return L[0];
}

/* The same row at 550 nm: order 2 by the table's paths over the shape. */
static void second_order_shape_carries_the_aureole(void **state)
{
    path_context pc;
    fm_sky *sky = desert_dust_sky(&pc, 2, 2, 550.0);
    enum { N = 4096 };
    double two[COLS], ratio[COLS];
    for (int j = 0; j < COLS; j++) {
        vec3 d = direction_from_elevation_azimuth(30.0 * FM_DEG, (180.0 - 180.0 * j / (COLS - 1)) * FM_DEG);
        double L[1] = {0.0};
        table_node_paths(sky, &pc, d, N, 9, (uint64_t)(200 + j), 0, L, NULL, NULL, NULL);
        two[j] = L[0] / N;
        double shape = next_order_shape(&sky->atm, sky->observer, d, sky->sun_dir, 0, observer_single_scatter, sky);
        ratio[j] = two[j] / shape;
        print_message("azimuth %5.1f from the sun: order 2 / shape %.3f\n", 180.0 * j / (COLS - 1), ratio[j]);
        assert_true(ratio[j] > 0.6 && ratio[j] < 1.2);
    }
    print_message("5th cosine over the mean: order 2 %.3f, order 2 / shape %.3f\n", cosine_share(two, 5),
                  cosine_share(ratio, 5));
    assert_true(cosine_share(two, 5) > 0.15);
    assert_true(fabs(cosine_share(ratio, 5)) < 0.03);
    fm_sky_destroy(sky);
}

/* The whole of it on a map: desert dust at sun 30, two seeds' final 256 x 128 maps, the RMS of their
 * relative luminance difference (sky and ground; the sun disk left out).  With the table fitted whole
 * it was 0.39% (seeds 1 and 2; 0.39 and 0.32% for seeds 3-4 and 5-6), with its parts through their
 * shapes 0.24% (0.25 and 0.17%). */
static void desert_dust_table_is_fitted_through_its_shapes(void **state)
{
    fm_sky_params p = fm_sky_params_default();
    p.biome = "desert-dust";
    fm_sky *sky = test_sky(&p);
    fm_image *a = test_render(sky, 256, FM_QUALITY_FINAL, 0, 1, 0, 1.0, 0);
    fm_image *b = test_render(sky, 256, FM_QUALITY_FINAL, 0, 2, 0, 1.0, 0);
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < a->height; y++)
        for (int x = 0; x < a->width; x++) {
            double ya = test_pixel_y(a, x, y), yb = test_pixel_y(b, x, y);
            assert_true(ya > 0.0 && yb > 0.0);
            sum += (ya / yb - 1.0) * (ya / yb - 1.0);
            n++;
        }
    double rms = sqrt(sum / n);
    print_message("desert dust, sun 30, 256 x 128 final: seeds 1 and 2 differ by %.3f%% RMS\n", 100.0 * rms);
    assert_true(rms < 0.0030);
    fm_image_destroy(a);
    fm_image_destroy(b);
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(second_order_matches_quadrature),
        cmocka_unit_test(table_orders_part_the_same_paths),
        cmocka_unit_test(aureole_is_order_two),
        cmocka_unit_test(second_order_shape_carries_the_aureole),
        cmocka_unit_test(desert_dust_table_is_fitted_through_its_shapes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

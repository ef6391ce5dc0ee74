/* The radiance table's irradiance weights (transport/sky_grid.h, sky_grid_irradiance_weights): the
 * weighted sum of the sky's nodes must equal the integral of the table's own interpolant times
 * sin(elevation) over the sky, computed here independently by a fine midpoint rule over
 * sky_grid_lookup, and come close to the integral of the smooth field the nodes sample. */
#include "check.h"

#include "base/units.h"
#include "transport/sky_grid.h"
#include "transport/sky_grid_refine.h"

#include <math.h>
#include <stdlib.h>

#define ROWS_SKY 20
#define ROWS_GROUND 12
#define COLS 16

/* A smooth sky: brighter toward the horizon and toward the sun (phi = 0); its irradiance
 * integral over the hemisphere is pi (1 + 0.6 * 2/3) + 0 (the cosine terms cancel over phi). */
static double field(double e, double phi) { return 1.0 + 0.6 * sin(e) + 0.25 * cos(e) * cos(phi); }

static void fill(sky_grid *g, double (*f)(double, double))
{
    for (int i = 0; i < sky_grid_nodes(g); i++) {
        double e, phi;
        sky_grid_node_angles(g, i, &e, &phi);
        sky_grid_set(g, i, 0, (float)f(e, phi));
    }
}

static double weighted_sum(const sky_grid *g)
{
    double *w = malloc(sizeof(double) * ROWS_SKY * COLS), sum = 0.0;
    assert_non_null(w);
    sky_grid_irradiance_weights(g, w);
    for (int i = 0; i < ROWS_SKY * COLS; i++)
        sum += w[i] * g->values[i];
    free(w);
    return sum;
}

/* The interpolant's integral by the midpoint rule in (elevation, azimuth), both halves of phi. */
static double midpoint_integral(const sky_grid *g, int n)
{
    double sum = 0.0;
    float v;
    for (int i = 0; i < n; i++) {
        double e = (i + 0.5) / n * 0.5 * FM_PI;
        for (int j = 0; j < n; j++) {
            sky_grid_lookup(g, e, (j + 0.5) / n * FM_PI, &v);
            sum += v * sin(e) * cos(e);
        }
    }
    return sum * (0.5 * FM_PI / n) * (FM_PI / n) * 2.0;
}

static double one(double e, double phi)
{
    (void)e, (void)phi;
    return 1.0;
}
static double azimuthal(double e, double phi) { return cos(e) * cos(phi); }

static void constant_sky_gives_pi(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, 0.0, ROWS_SKY, ROWS_GROUND, COLS, 1, 0), FM_OK);
    fill(&g, one);
    check_rel(weighted_sum(&g), FM_PI, 1e-9, "constant radiance 1: irradiance pi");
    fill(&g, azimuthal);
    check_abs(weighted_sum(&g), 0.0, 1e-9, "cos(phi) radiance: no irradiance");
    sky_grid_free(&g);
}

static void weights_integrate_the_interpolant(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, 0.0, ROWS_SKY, ROWS_GROUND, COLS, 1, 0), FM_OK);
    fill(&g, field);
    double sum = weighted_sum(&g), mid = midpoint_integral(&g, 2000), exact = FM_PI * 1.4;
    print_message("irradiance: weights %.8f, interpolant by midpoints %.8f, field %.8f\n", sum, mid, exact);
    check_rel(sum, mid, 2e-6, "weights = the interpolant's integral");
    check_rel(sum, exact, 1e-3, "the interpolant's integral near the field's");
    /* the ground's rows carry no weight: changing them changes nothing */
    for (int i = ROWS_SKY * COLS; i < sky_grid_nodes(&g); i++)
        g.values[i] = 1e6f;
    check_rel(weighted_sum(&g), sum, 1e-12, "ground rows ignored");
    sky_grid_free(&g);
}

/* The preview's (and the live sky's) multiple-scattering table (render/quality.c). */
#define PREVIEW_ROWS_SKY 12
#define PREVIEW_ROWS_GROUND 8
#define PREVIEW_COLS 12

/* Deep twilight's clear sky in shape: a glow that climbs steeply toward the horizon and toward the
 * sun's azimuth (convex in both), over a dim sky; the same below the horizon, mirrored. */
static double twilight_glow(double e, double phi)
{
    return 0.1 + exp(-fabs(e) / (12.0 * FM_DEG)) * (0.4 + exp(-(1.0 - cos(phi)) / 0.4));
}

/* The mean over the sky of lookup / field - 1 on an equirectangular map's pixels (what a map's bias
 * is), and the irradiance of g's weights against the field's own (a fine midpoint rule). */
static void read_back(const sky_grid *g, double *map_bias, double *irradiance_error)
{
    const int n = 400;
    double sum = 0.0, field_e = 0.0, table_e = 0.0;
    float v;
    for (int i = 0; i < n; i++) {
        double e = (i + 0.5) / n * 0.5 * FM_PI;
        for (int j = 0; j < n; j++) {
            double phi = (j + 0.5) / n * FM_PI, f = twilight_glow(e, phi);
            sky_grid_lookup(g, e, phi, &v);
            sum += v / f - 1.0;
            field_e += f * sin(e) * cos(e);
        }
    }
    *map_bias = sum / ((double)n * n);
    field_e *= (0.5 * FM_PI / n) * (FM_PI / n) * 2.0;
    const int m = g->rows_sky * g->cols;
    double *w = malloc(sizeof(double) * (size_t)m);
    assert_non_null(w);
    sky_grid_irradiance_weights(g, w);
    for (int i = 0; i < m; i++)
        table_e += w[i] * g->values[i];
    free(w);
    *irradiance_error = table_e / field_e - 1.0;
}

/* sky_grid_refine: a coarse table read bilinearly lies above a field that bends upward between its
 * nodes (the live sky's deep twilight maps were about 1 % bright from it); read through the cubic
 * refinement, within 0.1 %, and the refined table keeps the coarse nodes' values where they meet. */
static void refined_table_follows_a_convex_sky(void **state)
{
    (void)state;
    sky_grid coarse, fine;
    assert_int_equal(sky_grid_init(&coarse, 0.0, PREVIEW_ROWS_SKY, PREVIEW_ROWS_GROUND, PREVIEW_COLS, 1, 0), FM_OK);
    fill(&coarse, twilight_glow);
    assert_int_equal(sky_grid_refine(&coarse, 8, &fine), FM_OK);
    assert_int_equal(fine.rows_sky, 89);
    assert_int_equal(fine.rows_ground, 57);
    assert_int_equal(fine.cols, 89);
    for (int r = 0; r < PREVIEW_ROWS_SKY + PREVIEW_ROWS_GROUND; r++)
        for (int c = 0; c < PREVIEW_COLS; c++) {
            int fr = r < PREVIEW_ROWS_SKY ? 8 * r : fine.rows_sky + 8 * (r - PREVIEW_ROWS_SKY);
            assert_true(fine.values[fr * fine.cols + 8 * c] == coarse.values[r * PREVIEW_COLS + c]);
        }
    for (int i = 0; i < sky_grid_nodes(&fine); i++)
        assert_true(fine.values[i] >= 0.1f * 0.999f);
    double coarse_bias, coarse_e, fine_bias, fine_e;
    read_back(&coarse, &coarse_bias, &coarse_e);
    read_back(&fine, &fine_bias, &fine_e);
    print_message("map bias %+.4f %% coarse, %+.4f %% refined; irradiance %+.4f %% coarse, %+.4f %% refined\n",
                  100 * coarse_bias, 100 * fine_bias, 100 * coarse_e, 100 * fine_e);
    assert_true(coarse_bias > 0.005); /* the fault this guards against is there to see */
    check_abs(fine_bias, 0.0, 1e-3, "the refined table's map within 0.1 % of the field");
    check_abs(fine_e, 0.0, 1e-3, "the refined table's irradiance within 0.1 % of the field's");
    sky_grid_free(&coarse);
    sky_grid_free(&fine);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(constant_sky_gives_pi),
        cmocka_unit_test(weights_integrate_the_interpolant),
        cmocka_unit_test(refined_table_follows_a_convex_sky),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

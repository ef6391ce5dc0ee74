/* The radiance table's irradiance weights (transport/sky_grid.h, sky_grid_irradiance_weights): the
 * weighted sum of the sky's nodes must equal the integral of the table's own interpolant times
 * sin(elevation) over the sky, computed here independently by a fine midpoint rule over
 * sky_grid_lookup, and come close to the integral of the smooth field the nodes sample. */
#include "check.h"

#include "base/units.h"
#include "transport/sky_grid.h"

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(constant_sky_gives_pi),
        cmocka_unit_test(weights_integrate_the_interpolant),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

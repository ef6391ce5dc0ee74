/* The live sky's shared walks (ms_table_fill_shared, path_context.suns): one set of
 * multiple-scattering walks scored for two suns gives each sun's table what a table of its own paths
 * gives, within their noise.  The two suns' tables in hazy air (urban: the sun guide draws about
 * both suns, so its mixture's density must count both) against tables traced alone with another
 * seed, node by node: the mean over the sky's nodes of the difference in standard errors is 0 within
 * what chance allows for that many nodes.  A low sun behind the haze (the rising segments'
 * estimator, ms_table.c) leads the walks it shares: its table is, bit for bit, the one its own walks
 * give, and a high sun scored on them gets its own table's expectation. */
#include "check.h"
#include "render/ms_table.h"
#include "render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SUNS 2
static const double sun_deg[SUNS] = {11.0, 67.5}; /* two nodes of one group of the live sky's */

/* One sun's table in the making. */
typedef struct table_build {
    fm_sky *sky;
    fm_render_params rp;
    ms_table ms;
    render_job job;
} table_build;

/* The fast path's job for the sky with the sun at elevation_deg (azimuth 180) up to its paths,
 * at preview quality, with the given seed. */
static void begin(const fm_sky *sky, double elevation_deg, uint64_t seed, table_build *b)
{
    memset(b, 0, sizeof *b);
    b->sky = malloc(sizeof *b->sky);
    assert_non_null(b->sky);
    *b->sky = *sky; /* the tables shared, read-only, as the live sky's copies (sky_sun.c) */
    fm_error err;
    assert_int_equal(fm_sky_set_sun(b->sky, elevation_deg, 180.0, &err), FM_OK);
    b->rp = fm_render_params_default();
    b->rp.quality = FM_QUALITY_PREVIEW;
    b->job.sky = b->sky;
    b->job.params = &b->rp;
    b->job.ms = &b->ms;
    b->job.channels = 3;
    b->job.q = render_quality_settings(FM_QUALITY_PREVIEW, 1.0);
    b->job.seed = seed;
    assert_int_equal(render_fast_tables_begin(&b->job, &err), FM_OK);
    assert_true(render_fast_tables_shareable(&b->job));
}

static void finish(table_build *b)
{
    sky_grid_free(&b->job.ss);
    ms_table_free(&b->ms);
    ground_irradiance_free(&b->job.ground);
    deck_base_free(&b->job.deck);
    free(b->sky);
}

/* The mean over the sky's nodes of (a - b) / sqrt(var_a + var_b), for y (order 2) or later (3 up). */
static double mean_z(const ms_table *a, const ms_table *b, int later, int *nodes)
{
    const int n = a->grid.rows_sky * a->grid.cols;
    double sum = 0.0;
    *nodes = 0;
    for (int i = 0; i < n; i++) {
        double ya = later ? a->later_y[i] : a->y[i], yb = later ? b->later_y[i] : b->y[i];
        double var = later ? a->later_var[i] + b->later_var[i] : a->var[i] + b->var[i];
        if (!(var > 0.0))
            continue;
        sum += (ya - yb) / sqrt(var);
        (*nodes)++;
    }
    return *nodes ? sum / *nodes : 0.0;
}

static void shared_walks_are_unbiased(void **state)
{
    (void)state;
    fm_sky_params p = fm_sky_params_default();
    p.biome = "urban";
    fm_sky *sky = test_sky(&p);
    table_build shared[SUNS], alone[SUNS];
    render_job *jobs[SUNS];
    fm_error err;
    for (int s = 0; s < SUNS; s++) {
        begin(sky, sun_deg[s], 11, &shared[s]);
        begin(sky, sun_deg[s], 22 + (uint64_t)s, &alone[s]);
        jobs[s] = &shared[s].job;
        assert_int_equal(render_fast_tables_fill(&alone[s].job, sun_deg[s] * FM_DEG, &err), FM_OK);
    }
    assert_int_equal(render_fast_tables_fill_shared(jobs, SUNS, &err), FM_OK);
    for (int s = 0; s < SUNS; s++)
        for (int later = 0; later < 2; later++) {
            int nodes;
            double z = mean_z(&shared[s].ms, &alone[s].ms, later, &nodes);
            char what[96];
            snprintf(what, sizeof what, "sun %.1f, orders %s: mean of %d nodes' differences in standard errors",
                     sun_deg[s], later ? "3 up" : "2", nodes);
            print_message("%s: %+.3f\n", what, z);
            assert_true(nodes > 100);
            /* independent nodes: the mean of n standard normals has the standard error 1 / sqrt(n) */
            check_abs(z, 0.0, 4.0 / sqrt(nodes), what);
        }
    for (int s = 0; s < SUNS; s++) {
        finish(&shared[s]);
        finish(&alone[s]);
    }
    fm_sky_destroy(sky);
}

/* Whether two tables hold the same sums, node by node and wavelength by wavelength. */
static int same_sums(const ms_table *a, const ms_table *b, int K)
{
    const size_t n = (size_t)sky_grid_nodes(&a->grid) * (size_t)K;
    return a->paths == b->paths && !memcmp(a->sum, b->sum, n * sizeof *a->sum) &&
           !memcmp(a->later_sum, b->later_sum, n * sizeof *a->later_sum);
}

static void rising_sun_leads_its_walks(void **state)
{
    (void)state;
    static const double deg[SUNS] = {2.0, 35.0}; /* the live sky's group of the node at 2 degrees */
    fm_sky_params p = fm_sky_params_default();
    p.biome = "urban";
    fm_sky *sky = test_sky(&p);
    table_build shared[SUNS], own, high;
    render_job *jobs[SUNS];
    fm_error err;
    for (int s = 0; s < SUNS; s++) {
        begin(sky, deg[s], 11, &shared[s]);
        jobs[s] = &shared[s].job;
    }
    assert_true(ms_table_walk_rising(jobs[0]) && !ms_table_walk_rising(jobs[1]));
    begin(sky, deg[0], 11, &own);
    begin(sky, deg[1], 33, &high);
    assert_int_equal(render_fast_tables_fill(&own.job, deg[0] * FM_DEG, &err), FM_OK);
    assert_int_equal(render_fast_tables_fill(&high.job, deg[1] * FM_DEG, &err), FM_OK);
    assert_int_equal(render_fast_tables_fill_shared(jobs, SUNS, &err), FM_OK);
    assert_true(own.ms.rising_segments && shared[0].ms.rising_segments);
    assert_true(same_sums(&shared[0].ms, &own.ms, sky->atm.grid.count));
    for (int later = 0; later < 2; later++) {
        int nodes;
        double z = mean_z(&shared[1].ms, &high.ms, later, &nodes);
        print_message("sun %.1f on the walks of sun %.1f, orders %s: mean of %d nodes' differences in standard "
                      "errors %+.3f\n", deg[1], deg[0], later ? "3 up" : "2", nodes, z);
        assert_true(nodes > 100);
        check_abs(z, 0.0, 4.0 / sqrt(nodes), "the high sun's table on the rising sun's walks");
    }
    for (int s = 0; s < SUNS; s++)
        finish(&shared[s]);
    finish(&own);
    finish(&high);
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shared_walks_are_unbiased),
        cmocka_unit_test(rising_sun_leads_its_walks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

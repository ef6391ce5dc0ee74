/* A cloud deck above the observer (issue 48; docs/decisions/2026-12-06-cloud-column.md): the fast
 * path's multiple-scattering table from the plane-parallel column (render/fog_table.h), as in fog,
 * against the reference estimator's plain path tracing of every order, at 550 nm in the built-in
 * atmosphere (rural aerosols, ozone, the sphere), the observer on the ground under the altostratus
 * preset (3-4 km, optical depth 10), sun 30 degrees up at azimuth 180: the diffuse irradiance at the
 * ground and views across the sky, a few near the horizon (where the view meets the base some
 * 40-170 km away and the plane differs from the sphere) and a few 4-12 degrees from the sun, within
 * 2 % plus 3 standard errors (the decision record's figures).
 * Where it applies: from FOG_TABLE_MIN_TAU, with the sun FOG_TABLE_MIN_SUN_DEG_PER_KM degrees per km
 * of the layer's base up or more (a thin layer: test_thin_layers.c).
 * Faults it fails on: the deck's layer left out of the column, the ground's reflection left out of
 * the column (the decision record says by how much), the base's sun bound left out.
 * About 40 s of CPU, nearly all of it the path tracer. */
#include "check.h"

#include "column_tables.h"
#include "render/fog_table.h"
#include "render/render.h"
#include "thick_media_cases.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define PATHS 100000
#define TOLERANCE 0.02

static fm_sky *deck_sky(const char *clouds, double sun_deg)
{
    fm_sky_params p = fm_sky_params_default();
    p.clouds = clouds;
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = sun_deg;
    p.sun_azimuth_deg = 180.0;
    return test_sky(&p);
}

/* Views (elevation, azimuth from the sun's, degrees): near the horizon, across the sky, and 4 to 12
 * degrees from the sun. */
static const double views[][2] = {{1, 90},  {3, 180}, {6, 0},  {15, 90}, {60, 180}, {85, 0},
                                  {30, 90}, {45, 45}, {34, 5}, {38, 0},  {22, 0},   {42, 0}};

static void deck_against_the_path_tracer(const char *clouds, double sun_deg)
{
    fm_sky *sky = deck_sky(clouds, sun_deg);
    column_tables t;
    column_tables_start(sky, 0, 0, &t);
    assert_null(t.tw);
    assert_true(fog_table_applies(&t.job));
    column_tables_make(&t);
    char what[96];
    double diffuse, se;
    ground_irradiance_lookup(&t.job.ground, sky->sun_dir.z, &diffuse);
    const double E = cloud_irradiance(sky, 1.0, 3 * PATHS, 7, &se);
    snprintf(what, sizeof what, "%s, sun %g: diffuse irradiance at the ground", clouds, sun_deg);
    check_within_reference(diffuse, E, se, TOLERANCE, what);
    path_context all = sky_path_context(sky, 1, 0);
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        const double e = views[i][0] * FM_DEG, phi = views[i][1] * FM_DEG;
        const double ref = test_path_radiance(&all, sky->observer, render_view_direction(sky, e, phi), PATHS, 9, i, &se);
        snprintf(what, sizeof what, "%s, sun %g: radiance at elevation %.0f, azimuth %.0f", clouds, sun_deg, views[i][0],
                 views[i][1]);
        check_within_reference(column_tables_radiance(&t, e, phi), ref, se, TOLERANCE, what);
    }
    column_tables_free(&t);
    fm_sky_destroy(sky);
}

static void altostratus_against_the_path_tracer(void **state)
{
    (void)state;
    deck_against_the_path_tracer("altostratus", 30.0);
}

/* Where the column applies under an elevated layer: from FOG_TABLE_MIN_TAU up, with the sun
 * FOG_TABLE_MIN_SUN_DEG_PER_KM degrees per km of the layer's base up or more; a thinner layer from
 * FOG_TABLE_MIN_TAU_THIN up, with the sun FOG_TABLE_THIN_MIN_SUN_DEG up or more, or
 * FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG for a layer of ice (FOG_TABLE_THIN_LOW_SUN_DEG from
 * FOG_TABLE_THIN_LOW_SUN_MIN_TAU up); fog alone around the observer of FOG_TABLE_MIN_TAU_FOG or more
 * from FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG (docs/decisions/2026-12-07-shallow-fog.md); under a cirrostratus,
 * the day's column from FOG_TABLE_FOG_UNDER_THIN_SUN_DEG + FOG_TABLE_BLEND_DEG (2026-12-07-fog-under-thin-layers.md). */
static void where_the_column_applies(void **state)
{
    (void)state;
    static const struct {
        const char *clouds;
        double tau, sun_deg;
        int applies;
    } cases[] = {{"altostratus", FOG_TABLE_MIN_TAU, 3.0 * FOG_TABLE_MIN_SUN_DEG_PER_KM + 0.01, 1},
                 {"altostratus", FOG_TABLE_MIN_TAU, 3.0 * FOG_TABLE_MIN_SUN_DEG_PER_KM - 0.01, 0},
                 {"altostratus", 0.99 * FOG_TABLE_MIN_TAU, FOG_TABLE_THIN_MIN_SUN_DEG + 0.01, 1},
                 {"altostratus", 0.99 * FOG_TABLE_MIN_TAU, FOG_TABLE_THIN_MIN_SUN_DEG - 0.01, 0},
                 {"altostratus", FOG_TABLE_MIN_TAU_THIN, 60.0, 1},
                 {"altostratus", 0.99 * FOG_TABLE_MIN_TAU_THIN, 60.0, 0},
                 {"cirrostratus", 1.0, FOG_TABLE_THIN_MIN_SUN_DEG + 0.01, 1},
                 {"cirrostratus", 1.0, FOG_TABLE_THIN_MIN_SUN_DEG - 0.01, 1},
                 {"cirrostratus", 1.0, FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG + 0.01, 1},
                 {"cirrostratus", 0.99 * FOG_TABLE_THIN_LOW_SUN_MIN_TAU, FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG - 0.01, 0},
                 {"cirrostratus", FOG_TABLE_THIN_LOW_SUN_MIN_TAU, FOG_TABLE_THIN_LOW_SUN_DEG + 0.01, 1},
                 {"cirrostratus", FOG_TABLE_THIN_LOW_SUN_MIN_TAU, FOG_TABLE_THIN_LOW_SUN_DEG - 0.01, 0},
                 {"cirrostratus", FOG_TABLE_MIN_TAU, 8.0 * FOG_TABLE_MIN_SUN_DEG_PER_KM - 0.01, 0},
                 {"stratus", 30.0, 3.0, 1},
                 /* fog alone around the observer from FOG_TABLE_MIN_TAU_FOG, not under another layer */
                 {"fog", 1.0, FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG, 1},
                 {"fog", 1.0, FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG - 0.01, 0},
                 {"fog", FOG_TABLE_MIN_TAU_FOG, FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG, 1},
                 {"fog", 0.99 * FOG_TABLE_MIN_TAU_FOG, FOG_TABLE_THIN_MIN_SUN_DEG - 0.01, 0},
                 /* under a cirrostratus, without the column lit from above: the day's column above its blend */
                 {"fog,cirrostratus", 1.0, FOG_TABLE_FOG_UNDER_THIN_SUN_DEG + FOG_TABLE_BLEND_DEG + 0.01, 1},
                 {"fog,cirrostratus", 1.0, FOG_TABLE_FOG_UNDER_THIN_SUN_DEG + FOG_TABLE_BLEND_DEG - 0.01, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fm_sky_params p = fm_sky_params_default();
        p.wavelength_nm = 550.0;
        p.sun_elevation_deg = cases[i].sun_deg;
        p.clouds = cases[i].clouds;
        p.cloud_tau550 = cases[i].tau;
        fm_sky *sky = test_sky(&p);
        fm_render_params rp = fm_render_params_default();
        render_job job = {.sky = sky, .params = &rp};
        print_message("%s, tau %g, sun %.2f: the column %s\n", cases[i].clouds, cases[i].tau, cases[i].sun_deg,
                      fog_table_applies(&job) ? "applies" : "does not");
        assert_int_equal(fog_table_applies(&job), cases[i].applies);
        fm_sky_destroy(sky);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(where_the_column_applies),
        cmocka_unit_test(altostratus_against_the_path_tracer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Fog around the observer (issue 48, item 5; docs/decisions/2026-12-06-fog-column.md):
 *  - the column solver (transport/plane_column.h) against the tests' own adding-doubling
 *    (adding_doubling.c, written apart) for one Henyey-Greenstein layer over a Lambertian ground,
 *    whole and cut into two and three layers: the bottom radiance's Fourier modes, the flux there and
 *    the reflection at the top to 1e-4 (they start doubling at 1e-6 and 1e-9), and between the cuts
 *    of a layer that absorbs nothing the net flux equal to the bottom's; with every layer's beam
 *    cosine (pseudo-spherical) other than the sun's, the radiances of the column at that cosine;
 *  - the fast path's fog sky (the multiple-scattering table from the column, render/fog_table.h)
 *    against the reference estimator's plain path tracing of every order, fog of 200 m visibility
 *    (0-200 m), sun 30 degrees up, 550 nm: in a plane alone and in the built-in atmosphere, the
 *    observer on the ground (the diffuse irradiance there and radiances across the sky) and at 100 m
 *    (radiances up and down), within 1 % plus 3 standard errors of the path tracer, and within 3 %
 *    plus 3 standard errors 4 to 9 degrees from the sun (the peak's light there);
 *    and with the sun 8 and 0.2 degrees up (FOG_TABLE_MIN_SUN_DEG), within 2 % plus 3 standard errors;
 *  - where the column applies (fog alone from 0.2 degrees, and below 3 down to -18 lit by the sky above
 *    the fog, test_fog_twilight; under another cloud from 8).
 * Faults it fails on: the air above the fog left out of the column (the irradiance 17 % high), the
 * ground's reflection left out of the column (every check), the ground's light not taken from the
 * views looking down (the observer at 100 m), the air's beam cosines not pseudo-spherical (the low
 * sun), the air in thick layers (the lowest sun), a layer's or the ground's beam response left per its
 * own cosine (the layers' cosines), the clouds' threshold left out (where it applies), the negative
 * lobe of the peak's light left out (8 degrees from the sun: +13 % at 100 m, +7 % in the plane).
 * About 60 s of CPU, nearly all of it the path tracer. */
#include "check.h"

#include "adding_doubling.h"
#include "base/quadrature.h"
#include "base/rng.h"
#include "column_tables.h"
#include "thick_media_cases.h"
#include "transport/path.h"
#include "render/fog_table.h"
#include "render/render.h"
#include "transport/plane_column.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#define N_MU 5
static const double view_mu[N_MU] = {0.05, 0.2, 0.5, 0.8, 1.0};

/* One Henyey-Greenstein layer (delta-M scaled by adding_doubling.c), cut into `cuts` layers of the
 * given shares of its optical depth: the bottom radiance's modes and the flux must be the reference's. */
static void layer_as_column(double tau, double g, double ssa, double albedo, int cuts, const double *share)
{
    ad_problem p = {.tau = tau, .ssa = ssa, .ground_albedo = albedo, .mu0 = 0.5, .phase = ad_phase_hg,
                    .phase_ctx = &g, .streams = 12, .delta_m = 1, .n_mu = N_MU, .mu = view_mu};
    ad_solution s;
    assert_int_equal(ad_solve(&p, &s), 0);
    plane_layer layer[4];
    for (int i = 0; i < cuts; i++)
        layer[i] = (plane_layer){.tau = s.tau_scaled * share[i], .ssa = s.ssa_scaled, .chi = s.moments};
    plane_column c = {.streams = p.streams, .layer_count = cuts, .layer = layer, .ground_albedo = albedo,
                      .mu0 = p.mu0, .n_mu = N_MU, .mu = view_mu};
    double modes[N_MU * 24], flux;
    assert_int_equal(plane_column_bottom(&c, modes, &flux), FM_OK);
    char what[96];
    for (int k = 0; k < N_MU; k++)
        for (int m = 0; m < s.modes; m++) {
            snprintf(what, sizeof what, "tau %g in %d: mu %g mode %d", tau, cuts, view_mu[k], m);
            check_abs(modes[k * s.modes + m], s.bottom[k * s.modes + m], 1e-4 * fabs(s.bottom[k * s.modes]) + 1e-12, what);
        }
    double expected = s.flux_down_diffuse + s.flux_down_direct;
    snprintf(what, sizeof what, "tau %g in %d: flux", tau, cuts);
    check_rel(flux, expected, 1e-4, what);
    /* at the top, looking down: the column's reflection */
    assert_int_equal(plane_column_level(&c, 0, NULL, modes, NULL), FM_OK);
    for (int k = 0; k < N_MU; k++)
        for (int m = 0; m < s.modes; m++) {
            snprintf(what, sizeof what, "tau %g in %d: top, mu %g mode %d", tau, cuts, view_mu[k], m);
            check_abs(modes[k * s.modes + m], s.top[k * s.modes + m], 1e-4 * fabs(s.top[k * s.modes]) + 1e-12, what);
        }
    /* between the cuts, where nothing is absorbed: the net flux is the bottom's (Gauss nodes as views) */
    if (ssa == 1.0) {
        const gauss_rule *q = gauss_legendre_cached(16);
        double mu[16], down[16 * 24], up[16 * 24], f_level;
        for (int i = 0; i < 16; i++)
            mu[i] = 0.5 * (1.0 + q->x[i]);
        plane_column cq = c;
        cq.n_mu = 16;
        cq.mu = mu;
        double depth = 0.0;
        for (int level = 1; level < cuts; level++) {
            depth += layer[level - 1].tau;
            assert_int_equal(plane_column_level(&cq, level, down, up, &f_level), FM_OK);
            double net = f_level;
            for (int i = 0; i < 16; i++)
                net -= 2.0 * FM_PI * 0.5 * q->w[i] * mu[i] * up[i * s.modes] / p.mu0;
            snprintf(what, sizeof what, "tau %g in %d: net flux at level %d", tau, cuts, level);
            check_rel(net, (1.0 - albedo) * flux, 1e-4, what);
        }
    }
    ad_free(&s);
}

/* Every layer's beam cosine mu' (pseudo-spherical) in a column of the sun's mu0: the beam is the
 * plane column's at mu', so the radiances per unit F0 must be that column's. */
static void layer_cosines_as_the_sun(void **state)
{
    (void)state;
    double g = 0.85;
    ad_problem p = {.tau = 3.9, .ssa = 0.99, .ground_albedo = 0.2, .mu0 = 0.3, .phase = ad_phase_hg,
                    .phase_ctx = &g, .streams = 12, .delta_m = 1, .n_mu = N_MU, .mu = view_mu};
    ad_solution s;
    assert_int_equal(ad_solve(&p, &s), 0);
    plane_layer layer[2] = {{.tau = 0.4 * s.tau_scaled, .ssa = s.ssa_scaled, .chi = s.moments, .mu0 = 0.3},
                            {.tau = 0.6 * s.tau_scaled, .ssa = s.ssa_scaled, .chi = s.moments, .mu0 = 0.3}};
    plane_column at = {.streams = p.streams, .layer_count = 2, .layer = layer, .ground_albedo = 0.2, .mu0 = 0.3,
                       .n_mu = N_MU, .mu = view_mu};
    plane_column pseudo = at;
    pseudo.mu0 = 0.1;
    double want[N_MU * 24], got[N_MU * 24];
    assert_int_equal(plane_column_level(&at, 1, want, NULL, NULL), FM_OK);
    assert_int_equal(plane_column_level(&pseudo, 1, got, NULL, NULL), FM_OK);
    for (int i = 0; i < N_MU * s.modes; i++)
        check_abs(got[i], want[i], 1e-9 * fabs(want[i - i % s.modes]) + 1e-15, "layers' cosines 0.3, the sun's 0.1");
    ad_free(&s);
}

static void column_matches_adding_doubling(void **state)
{
    (void)state;
    const double one[] = {1.0}, two[] = {0.5, 0.5}, three[] = {0.1, 0.7, 0.2};
    layer_as_column(3.9, 0.85, 1.0, 0.2, 1, one);
    layer_as_column(3.9, 0.85, 1.0, 0.2, 2, two);
    layer_as_column(3.9, 0.85, 0.99, 0.3, 3, three);
    layer_as_column(0.3, 0.5, 0.9, 0.0, 3, three);
}

/* Fog of 200 m visibility (presets/clouds/fog.json: 0-200 m, optical depth 3.9) around an observer on
 * the ground, sun 30 degrees up at azimuth 180, 550 nm: in the built-in atmosphere (rural aerosols,
 * ozone, the sphere) or, plane, alone in a trace of air on a planet of radius 10^6 km. */
static fm_sky *fog_sky(int plane, double altitude_m, double sun_deg, char **path_out)
{
    const char *text = "{\"planet_radius_km\": 1000000, \"top_altitude_km\": 3, \"ground_albedo\": 0.2, "
                       "\"solar_irradiance\": 1, \"constituents\": [{\"name\": \"trace\", \"profile\": {\"type\": "
                       "\"exponential\", \"scale_height_km\": 8}, \"extinction\": 1e-12, \"single_scattering_albedo\": 1, "
                       "\"phase\": {\"type\": \"henyey-greenstein\", \"g\": 0}}]}";
    char *path = plane ? test_write_temp("fog", text) : NULL;
    fm_sky_params p = fm_sky_params_default();
    p.atmosphere_file = path;
    p.fog_visibility_m = 200.0;
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = sun_deg;
    p.sun_azimuth_deg = 180.0;
    p.observer_altitude_m = altitude_m;
    *path_out = path; /* the sky keeps reading its name: removed after it (drop_sky) */
    return test_sky(&p);
}

static void drop_sky(fm_sky *sky, char *path)
{
    fm_sky_destroy(sky);
    if (path)
        unlink(path);
    free(path);
}

/* The fast path's tables for the sky (render.h), as a render makes them. */
static void fast_tables(const fm_sky *sky, column_tables *t)
{
    column_tables_start(sky, 0, 1, t);
    assert_null(t->tw);
    column_tables_make(t);
}

/* Views (elevation, azimuth from the sun's, degrees): across the sky, and NEAR_SUN 4 to 9 degrees
 * from the sun (the first three and the last), where the tolerance is NEAR_SUN_TOLERANCE: there the
 * light scattered several times within the droplets' truncated peak (fog_peak.c, fog_peak_light) is
 * positive within about 5 degrees and takes light back beyond; with the observer at 100 m the views
 * there are still 1-3 % bright (the decision record). */
static const double views[][2] = {{30, 10}, {38, 0}, {22, 0}, {30, 30}, {50, 0}, {30, 90},
                                  {60, 180}, {10, 180}, {80, 0}, {3, 90}, {34, 0}};
#define NEAR_SUN(i) ((i) < 3 || (i) == 10)
#define NEAR_SUN_TOLERANCE 0.03
/* and, from inside the fog, looking down */
static const double views_down[][2] = {{-3, 90}, {-10, 0}, {-30, 180}, {-50, 90}, {-85, 0}};

/* The fast path's radiance (both tables) and the reference's toward (elevation, azimuth) in degrees. */
static void compare_view(const fm_sky *sky, const column_tables *t, const path_context *all, const double *view,
                         uint64_t item, double rel, const char *sky_name)
{
    const double e = view[0] * FM_DEG, phi = view[1] * FM_DEG;
    double se;
    double ref = test_path_radiance(all, sky->observer, render_view_direction(sky, e, phi), 200000, 9, item, &se);
    char what[96];
    snprintf(what, sizeof what, "%s: radiance at elevation %.0f, azimuth %.0f", sky_name, view[0], view[1]);
    check_within_reference(column_tables_radiance(t, e, phi), ref, se, rel, what);
}

/* plane: the fog alone; altitude_m: the observer's (0: the ground's irradiance too, 100: the views
 * looking down too) */
static void fog_against_the_path_tracer(int plane, double altitude_m)
{
    char *path;
    fm_sky *sky = fog_sky(plane, altitude_m, 30.0, &path);
    const char *name = plane ? "plane fog" : altitude_m > 0.0 ? "fog, observer at 100 m" : "fog";
    column_tables t;
    fast_tables(sky, &t);
    char what[96];
    double diffuse, se;
    if (altitude_m == 0.0) {
        ground_irradiance_lookup(&t.job.ground, sky->sun_dir.z, &diffuse);
        double E = cloud_irradiance(sky, 1.0, 200000, 7, &se);
        snprintf(what, sizeof what, "%s: diffuse irradiance at the ground", name);
        check_within_reference(diffuse, E, se, 0.01, what);
    }
    path_context all = sky_path_context(sky, 1, 0);
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++)
        /* on the ground all but two the low sun checks, else two views near the sun (one in the plane) and
         * two away */
        if (!(plane || altitude_m > 0.0) ? i != 6 && i != 8 : i == 1 || i == 5 || i == 6 || (i == 10 && !plane))
            compare_view(sky, &t, &all, views[i], i, NEAR_SUN(i) ? NEAR_SUN_TOLERANCE : 0.01, name);
    for (size_t i = 0; i < sizeof views_down / sizeof views_down[0] && altitude_m > 0.0; i++)
        compare_view(sky, &t, &all, views_down[i], 100 + i, 0.01, name);
    column_tables_free(&t);
    drop_sky(sky, path);
}

static void plane_fog_against_the_path_tracer(void **state)
{
    (void)state;
    fog_against_the_path_tracer(1, 0.0);
}

static void fog_in_the_atmosphere_against_the_path_tracer(void **state)
{
    (void)state;
    fog_against_the_path_tracer(0, 0.0);
}

static void fog_above_the_ground_against_the_path_tracer(void **state)
{
    (void)state;
    fog_against_the_path_tracer(0, 100.0);
}

/* A low sun, the built-in atmosphere, on the ground: the beam in the air above the fog
 * pseudo-spherical and the air in thin layers.  Without the first the light the air scatters into the
 * fog is dimmed by the plane's slant paths (+6 % and more opposite the sun at 8 degrees); with the
 * air in the layers 1, 3 and 10 km thick of the first version, the beam lights the air above 10 km as
 * if all of it were halfway down the ozone (+9 % at 1 degree, +14 % at 0.2).  The irradiance and views 20 degrees
 * or more from the sun, within 2 % plus 3 standard errors, at 8 degrees and at the lowest sun the
 * column takes (FOG_TABLE_MIN_SUN_DEG). */
static void fog_at_a_low_sun(double sun_deg, uint64_t seed, uint64_t item)
{
    char *path;
    fm_sky *sky = fog_sky(0, 0.0, sun_deg, &path);
    column_tables t;
    fast_tables(sky, &t);
    double diffuse, se;
    char what[96];
    ground_irradiance_lookup(&t.job.ground, sky->sun_dir.z, &diffuse);
    const double E = cloud_irradiance(sky, 1.0, 250000, seed, &se);
    snprintf(what, sizeof what, "sun %g: diffuse irradiance at the ground", sun_deg);
    check_within_reference(diffuse, E, se, 0.02, what);
    path_context all = sky_path_context(sky, 1, 0);
    static const double low_sun_views[][2] = {{60, 180}, {80, 0}, {30, 30}};
    snprintf(what, sizeof what, "sun %g", sun_deg);
    for (size_t i = 0; i < sizeof low_sun_views / sizeof low_sun_views[0]; i++)
        compare_view(sky, &t, &all, low_sun_views[i], item + i, 0.02, what);
    column_tables_free(&t);
    drop_sky(sky, path);
}

static void fog_at_a_low_sun_against_the_path_tracer(void **state)
{
    (void)state;
    fog_at_a_low_sun(8.0, 17, 200);
    fog_at_a_low_sun(FOG_TABLE_MIN_SUN_DEG, 19, 300);
}

/* Where the column applies: fog alone from FOG_TABLE_MIN_SUN_DEG up; with a cirrostratus above it
 * from FOG_TABLE_MIN_SUN_DEG_CLOUDS (below that the sun table under the cloud puts the air layers'
 * beam cosines off: the column at sun 3 degrees came out 56 times the paths' diffuse light). */
static void where_the_column_applies(void **state)
{
    (void)state;
    static const struct {
        const char *clouds;
        double sun_deg;
        int applies;
        int from_above; /* fog_table_from_above: the fog alone lit by the sky above it */
    } cases[] = {{NULL, FOG_TABLE_BLEND_TO_DEG, 1, 0},
                 {NULL, FOG_TABLE_BLEND_TO_DEG - 0.01, 1, 1},
                 {NULL, FOG_TABLE_MIN_SUN_DEG, 1, 1},
                 {NULL, FOG_TABLE_MIN_SUN_DEG - 0.01, 1, 1},
                 {NULL, -6.0, 1, 1},
                 {NULL, FOG_TABLE_TWILIGHT_MIN_SUN_DEG, 1, 1},
                 {NULL, FOG_TABLE_TWILIGHT_MIN_SUN_DEG - 0.1, 0, 0},
                 {"cirrostratus", FOG_TABLE_MIN_SUN_DEG_CLOUDS, 1, 0},
                 {"cirrostratus", FOG_TABLE_MIN_SUN_DEG_CLOUDS - 0.1, 0, 0},
                 {"cirrostratus", 3.0, 0, 0},
                 {"cirrostratus", -3.0, 0, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fm_sky_params p = fm_sky_params_default();
        p.fog_visibility_m = 200.0;
        p.wavelength_nm = 550.0;
        p.sun_elevation_deg = cases[i].sun_deg;
        p.clouds = cases[i].clouds;
        fm_sky *sky = test_sky(&p);
        fm_render_params rp = fm_render_params_default();
        render_job job = {.sky = sky, .params = &rp, .fog_from_above = 1};
        print_message("fog%s%s, sun %.2f: the column %s\n", cases[i].clouds ? " under " : "",
                      cases[i].clouds ? cases[i].clouds : "", cases[i].sun_deg, fog_table_applies(&job) ? "applies" : "does not");
        assert_int_equal(fog_table_applies(&job), cases[i].applies);
        assert_int_equal(fog_table_from_above(&job), cases[i].from_above);
        fm_sky_destroy(sky);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plane_fog_against_the_path_tracer),
        cmocka_unit_test(fog_in_the_atmosphere_against_the_path_tracer),
        cmocka_unit_test(fog_above_the_ground_against_the_path_tracer),
        cmocka_unit_test(fog_at_a_low_sun_against_the_path_tracer),
        cmocka_unit_test(where_the_column_applies),
        cmocka_unit_test(column_matches_adding_doubling),
        cmocka_unit_test(layer_cosines_as_the_sun),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

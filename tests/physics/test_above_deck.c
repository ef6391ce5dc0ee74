/* The observer above a cloud deck (issue 48: a mountain top or an aircraft over an overcast;
 * docs/decisions/2026-12-07-above-deck.md): the fast path's multiple-scattering table from the
 * plane-parallel column with the observer's level above the deck (render/fog_table.h), 550 nm, sun
 * 30 degrees up at azimuth 180, the stratus preset (0.5-1 km, optical depth 30):
 *  - in a plane alone (a trace of air on a planet of radius 10^6 km), the observer at 2 km: the
 *    radiance looking down (the deck's top and the ground under it) against the tests' own
 *    adding-doubling (adding_doubling.c, written apart) of the droplets' layer over the ground, at
 *    five depressions and three azimuths, within 1 %;
 *  - in the built-in atmosphere (rural aerosols, ozone, the sphere), the observer at 3 km: views up
 *    and down against the reference estimator's plain path tracing of every order, within 2 % plus 3
 *    standard errors, at sun 30 and at sun 3 (the column at several suns, each view down lit by the
 *    sun where it meets the deck: docs/decisions/2026-12-07-thin-layers-low-sun.md).
 * Faults it fails on: the droplets above the deck's top (its profile's edge) spread through the air
 * up to the next break (3 and 5 degrees down, +21 and +13 %); the sky's rows at the plane's view
 * cosines (5 degrees up away from the sun, +8.9 %); at sun 3, one sun for every view down.
 * Run with an argument SUN for the comparison with the path tracer at that sun alone.
 * About 40 s of CPU, nearly all of it the path tracer. */
#include "check.h"

#include "adding_doubling.h"
#include "column_tables.h"
#include "render/fog_table.h"
#include "render/render.h"
#include "sky.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#define PATHS 40000
#define TOLERANCE 0.02
#define PLANE_TOLERANCE 0.01

static fm_sky *deck_sky(const char *atmosphere_file, double altitude_m, double sun_deg)
{
    fm_sky_params p = fm_sky_params_default();
    p.atmosphere_file = atmosphere_file;
    p.clouds = "stratus";
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = sun_deg;
    p.sun_azimuth_deg = 180.0;
    p.observer_altitude_m = altitude_m;
    return test_sky(&p);
}

/* The fast path's tables for the sky (render.h), as a render makes them, from the column. */
static void fast_tables(const fm_sky *sky, column_tables *t)
{
    column_tables_start(sky, 0, 1, t);
    assert_null(t->tw);
    assert_true(fog_table_applies(&t->job));
    column_tables_make(t);
}

/* ---- in a plane, against adding-doubling ------------------------------------------------------ */

typedef struct droplets {
    const phase_function *phase;
} droplets;

static double droplet_phase(double x, const void *ctx)
{
    return phase_evaluate(((const droplets *)ctx)->phase, 0, x);
}

/* Depressions and azimuths: the cloudbow (scattering angle near 140 degrees: mu 0.1 at azimuth 150)
 * left out, where the single-scattering table's nodes smooth it by a percent. */
#define N_DOWN 5
static const double down_mu[N_DOWN] = {0.1, 0.3, 0.5, 0.8, 0.99};
static const double down_phi_deg[] = {0.0, 90.0, 120.0};

static void deck_from_above_against_adding_doubling(void **state)
{
    (void)state;
    const char *text = "{\"planet_radius_km\": 1000000, \"top_altitude_km\": 4, \"ground_albedo\": 0.2, "
                       "\"solar_irradiance\": 1, \"constituents\": [{\"name\": \"trace\", \"profile\": {\"type\": "
                       "\"exponential\", \"scale_height_km\": 8}, \"extinction\": 1e-12, \"single_scattering_albedo\": 1, "
                       "\"phase\": {\"type\": \"henyey-greenstein\", \"g\": 0}}]}";
    char *path = test_write_temp("above_deck", text);
    fm_sky *sky = deck_sky(path, 2000.0, 30.0);
    column_tables t;
    fast_tables(sky, &t);
    /* the droplets: the species with the largest optical depth (the trace's is ~1e-9) */
    const atmosphere *atm = &sky->atm;
    int c_max = 0;
    double tau = 0.0;
    for (int c = 0; c < atm->scattering_count; c++) {
        const double col = profile_column(&atm->species[c].profile) * atm->species_sigma_t[c][0];
        if (col > tau) {
            tau = col;
            c_max = c;
        }
    }
    const species *d = &atm->species[c_max];
    droplets ctx = {&d->phase};
    ad_problem p = {.tau = tau, .ssa = d->sigma_s[0] / (d->sigma_s[0] + d->sigma_a[0]), .ground_albedo = 0.2,
                    .mu0 = sky->sun_dir.z, .phase = droplet_phase, .phase_ctx = &ctx, .streams = 32, .delta_m = 1,
                    .n_mu = N_DOWN, .mu = down_mu};
    print_message("the droplets' layer: optical depth %.4g, albedo %.6f\n", p.tau, p.ssa);
    ad_solution s;
    assert_int_equal(ad_solve(&p, &s), 0);
    char what[96];
    int bad = 0;
    for (int k = 0; k < N_DOWN; k++)
        for (size_t j = 0; j < sizeof down_phi_deg / sizeof down_phi_deg[0]; j++) {
            const double phi = down_phi_deg[j] * FM_DEG, e = -asin(down_mu[k]);
            const double fast = column_tables_radiance(&t, e, phi), ref = ad_radiance_top(&s, k, phi);
            snprintf(what, sizeof what, "plane deck from 2 km: looking down at mu %.2f, azimuth %.0f", down_mu[k],
                     down_phi_deg[j]);
            const int ok = fabs(fast - ref) <= PLANE_TOLERANCE * ref;
            print_message("%s: fast path %.5g, adding-doubling %.5g (%+.2f%%)%s\n", what, fast, ref,
                          100.0 * (fast / ref - 1.0), ok ? "" : " FAILS");
            bad += !ok;
        }
    assert_int_equal(bad, 0);
    ad_free(&s);
    column_tables_free(&t);
    fm_sky_destroy(sky);
    unlink(path);
    free(path);
}

/* ---- in the atmosphere, against the path tracer ----------------------------------------------- */

/* Views (elevation, azimuth from the sun's, degrees): the sky above, down to 2 degrees up (where the
 * sphere's slant depth is finite and the plane's is not: fog_column.c, fog_sphere_sky_cosines), and the
 * deck below, from 3 degrees down (where the view meets the deck's top 40 km away) to the nadir (the
 * glory at -30/180 left out: the single-scattering table's nodes are a degree or two apart). */
static const double views[][2] = {{60, 180}, {40, 0},  {30, 20},  {20, 90},  {5, 180}, {5, 0},  {2, 90},
                                  {-3, 0},   {-5, 180}, {-10, 0}, {-20, 90}, {-45, 180}, {-60, 0}, {-85, 90}};

/* The stratus from 3 km at sun_deg: the number of views outside the tolerance. */
static int deck_from_above_at(double sun_deg)
{
    fm_sky *sky = deck_sky(NULL, 3000.0, sun_deg);
    column_tables t;
    fast_tables(sky, &t);
    path_context all = sky_path_context(sky, 1, 0);
    char what[96];
    int bad = 0;
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        const double e = views[i][0] * FM_DEG, phi = views[i][1] * FM_DEG;
        const double fast = column_tables_radiance(&t, e, phi);
        double se;
        const double ref = test_path_radiance(&all, sky->observer, render_view_direction(sky, e, phi), PATHS, 9, i, &se);
        snprintf(what, sizeof what, "stratus from 3 km, sun %g: radiance at elevation %.0f, azimuth %.0f", sun_deg,
                 views[i][0], views[i][1]);
        bad += !within_reference(fast, ref, se, TOLERANCE, what);
    }
    column_tables_free(&t);
    fm_sky_destroy(sky);
    return bad;
}

static void deck_from_above_against_the_path_tracer(void **state)
{
    (void)state;
    assert_int_equal(deck_from_above_at(30.0), 0);
}

/* At sun 3 a view 3 degrees down toward the sun meets the deck 40 km off, where the sun stands 0.37
 * degrees higher: the column at several suns (FOG_TABLE_ABOVE_LOCAL_SUN_DEG). */
static void deck_from_above_at_a_low_sun(void **state)
{
    (void)state;
    assert_int_equal(deck_from_above_at(3.0), 0);
}

int main(int argc, char **argv)
{
    if (argc == 2)
        return deck_from_above_at(atof(argv[1])) != 0;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(deck_from_above_against_adding_doubling),
        cmocka_unit_test(deck_from_above_against_the_path_tracer),
        cmocka_unit_test(deck_from_above_at_a_low_sun),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

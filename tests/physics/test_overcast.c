/* Under a thick overcast and in fog (issue 48, item 4), by the reference estimator at 550 nm or in
 * colour, on uniformly drawn directions of the upper hemisphere (radiance bands and halves of the
 * sky from the same paths; the horizontal irradiance is 2 pi <L mu>):
 *  - a stratus deck of optical depth 30 with its Mie phase function (diffraction peak and all) in a
 *    plane-parallel atmosphere, sun 60 degrees up, ground albedo 0.2, against adding-doubling
 *    (adding_doubling.h) given the same layer's optical depth, albedo and phase table: the diffuse
 *    irradiance at the ground, the zenith cap's over the horizon band's radiance and the sky toward
 *    the sun's azimuth over the sky away from it.  The reference's own numbers are the physics: its
 *    zenith is 2.3 times its horizon (mu 0.05) where the CIE standard overcast sky, L(theta) =
 *    Lz (1 + 2 cos theta) / 3, says 3 (diffusion theory's escape function (1 + 2 mu) gives 3 for
 *    isotropic scattering; the droplets' forward peak and the bright ground flatten it), and the two
 *    azimuths differ by less than 0.4 %;
 *  - the Overcast preset's deck (stratus, tau 30, 0.5-1.0 km) in the built-in atmosphere, in colour,
 *    sun 60 degrees up: the global horizontal illuminance (the disk is hidden: all of it diffuse)
 *    against the mean overcast sky of Krochmann & Seidl (1974, Lighting Res. Technol. 6, 165): zenith
 *    luminance 8.6 sin(h) + 0.123 kcd/m^2, as Radiance's gensky uses it, times 7 pi / 9 for the CIE
 *    overcast distribution, 18.5 klx at h = 60; measured overcast skies at one solar altitude spread
 *    over a factor of several with the deck's thickness, so the test asks for a factor 2.  Its zenith
 *    is 2-4 times its horizon band and the two azimuth halves agree;
 *  - fog (visibility 200 m, 0-200 m) with the observer inside, at 100 m, sun 60 degrees up: in a
 *    layer that absorbs (almost) nothing the net downward flux is the same at every depth, so the
 *    path-traced diffuse down minus up plus the direct beam at the observer must be adding-doubling's
 *    net flux at the bottom, (1 - albedo) times everything arriving there.
 * Each compares within 1 % plus 3 standard errors of the path tracer, which at this CI budget is
 * 2-4 % for a deck of optical depth 30 (bench/overcast.sh runs the same with 25 times the paths).
 * Faults these fail on: every layer's extinction 20 % high (cloud_layer.c): the deck's irradiance
 * 13 % low against adding-doubling (the fog's net flux moves only 3.5 %; its azimuth check fails);
 * the droplets' phase function sampled without its diffraction peak (the table's first 3 degrees
 * never drawn, weights unchanged): the deck's irradiance 60 % low, the overcast's illuminance 1.2 klx,
 * the fog's net flux 30 % low. */
#include "check.h"

#include "adding_doubling.h"
#include "base/quadrature.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#define SUN_ELEVATION 60.0
#define ALBEDO 0.2
#define ZENITH_CAP 0.8   /* mu above: the zenith cap (elevations above 53 degrees) */
#define HORIZON_BAND 0.2 /* mu below: the horizon band (below 11.5 degrees) */

/* The paths of each check times $FM_OVERCAST_PATHS (default 1; bench/overcast.sh: 25). */
static int paths(int n)
{
    const char *x = getenv("FM_OVERCAST_PATHS");
    double scale = x ? atof(x) : 1.0;
    return (int)(n * (scale > 0.0 ? scale : 1.0));
}

/* What the paths saw: radiance (or luminance, cd m^-2) means with their standard errors. */
typedef struct dome {
    double E, E_se;             /* horizontal irradiance 2 pi <L mu> */
    double band[2], band_se[2]; /* [0] the zenith cap, [1] the horizon band */
    double half[2], half_se[2]; /* [0] toward the sun's azimuth, [1] away from it */
} dome;

typedef struct moments {
    double s, s2;
    int n;
} moments;

static void add(moments *m, double v)
{
    m->s += v;
    m->s2 += v * v;
    m->n++;
}

static double mean_of(const moments *m, double *se)
{
    double mean = m->s / m->n;
    *se = sqrt(fmax(0.0, m->s2 / m->n - mean * mean) / m->n);
    return mean;
}

/* N paths from the observer on directions uniform over the upper hemisphere; the sun is due south
 * (azimuth 180, -Y).  Colour skies give luminance (683 Y). */
static dome sample_dome(const fm_sky *sky, int N, uint64_t seed)
{
    const spectral_grid *g = &sky->atm.grid;
    path_context all = sky_path_context(sky, 1, 0);
    moments e = {0}, band[2] = {{0}}, half[2] = {{0}};
    for (int i = 0; i < N; i++) {
        rng r = rng_for(seed, 0, (uint64_t)i);
        double mu = rng_uniform(&r), phi = 2.0 * FM_PI * rng_uniform(&r), s = sqrt(1.0 - mu * mu);
        vec3 d = v3(s * sin(phi), s * cos(phi), mu);
        double L[FM_MAX_WAVELENGTHS] = {0}, v = 0.0;
        path_trace(&all, sky->observer, d, i % g->count, &r, L);
        if (g->colour)
            for (int k = 0; k < g->count; k++)
                v += 683.0 * L[k] * g->xyz_weight[k][1];
        else
            v = L[0];
        add(&e, 2.0 * FM_PI * v * mu);
        if (mu > ZENITH_CAP || mu < HORIZON_BAND)
            add(&band[mu > ZENITH_CAP ? 0 : 1], v);
        add(&half[d.y < 0.0 ? 0 : 1], v);
    }
    dome out;
    out.E = mean_of(&e, &out.E_se);
    for (int j = 0; j < 2; j++) {
        out.band[j] = mean_of(&band[j], &out.band_se[j]);
        out.half[j] = mean_of(&half[j], &out.half_se[j]);
    }
    return out;
}

/* a / b and its standard error from theirs (independent) */
static double ratio(double a, double a_se, double b, double b_se, double *se)
{
    double q = a / b;
    *se = q * sqrt((a_se / a) * (a_se / a) + (b_se / b) * (b_se / b));
    return q;
}

static void check_within(double got, double se, double expected, const char *what)
{
    print_message("%s: path tracer %.5g +- %.2g%%, expected %.5g (%+.2f%%)\n", what, got, 100.0 * se / got, expected,
                  100.0 * (got / expected - 1.0));
    check_abs(got, expected, 0.01 * fabs(expected) + 3.0 * se, what);
}

/* ---- a plane-parallel deck against adding-doubling ------------------------------------------- */

/* Clear air reduced to a trace (a custom atmosphere must hold one constituent), a planet of radius
 * 10^6 km (a plane over the kilometres a path wanders), top at 3 km, F0 = 1; the cloud from
 * presets/clouds/ as the options give it. */
static fm_sky *plane_sky(const char *cloud, double tau, double base_km, double thickness_km, double fog_m,
                         double altitude_m, char **path)
{
    char text[1024];
    snprintf(text, sizeof text,
             "{\"planet_radius_km\": 1000000, \"top_altitude_km\": 3, \"ground_albedo\": %g, \"solar_irradiance\": 1, "
             "\"constituents\": [{\"name\": \"trace\", \"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, "
             "\"extinction\": 1e-12, \"single_scattering_albedo\": 1, \"phase\": {\"type\": \"henyey-greenstein\", "
             "\"g\": 0}}]}",
             ALBEDO);
    *path = test_write_temp("overcast", text);
    fm_sky_params p = fm_sky_params_default();
    p.atmosphere_file = *path;
    p.clouds = cloud;
    p.cloud_tau550 = tau;
    p.cloud_base_km = base_km;
    p.cloud_thickness_km = thickness_km;
    p.fog_visibility_m = fog_m;
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = SUN_ELEVATION;
    p.sun_azimuth_deg = 180.0;
    p.observer_altitude_m = altitude_m;
    return test_sky(&p);
}

static void drop(fm_sky *sky, char *path)
{
    fm_sky_destroy(sky);
    unlink(path);
    free(path);
}

static double species_phase(double cos_theta, const void *ctx)
{
    return phase_evaluate(ctx, 0, cos_theta);
}

/* Adding-doubling for the sky's last constituent (its cloud) as a homogeneous layer of optical depth
 * tau, at the Gauss nodes of the zenith cap and the horizon band. */
#define NODES 8
static ad_solution deck_reference(const fm_sky *sky, double tau, double mu[2 * NODES])
{
    const species *sp = &sky->atm.species[sky->atm.species_count - 1];
    const gauss_rule *q = gauss_legendre_cached(NODES);
    for (int j = 0; j < NODES; j++) {
        mu[j] = ZENITH_CAP + (1.0 - ZENITH_CAP) * 0.5 * (q->x[j] + 1.0);
        mu[NODES + j] = HORIZON_BAND * 0.5 * (q->x[j] + 1.0);
    }
    ad_problem p = {.tau = tau, .ssa = sp->sigma_s[0] / (sp->sigma_s[0] + sp->sigma_a[0]), .ground_albedo = ALBEDO,
                    .mu0 = sin(SUN_ELEVATION * FM_DEG), .phase = species_phase, .phase_ctx = &sp->phase,
                    .streams = 16, .delta_m = 1, .n_mu = 2 * NODES, .mu = mu};
    ad_solution s;
    if (ad_solve(&p, &s))
        fail_msg("ad_solve failed");
    return s;
}

/* The reference's mean radiance over band b (0: zenith cap, 1: horizon band) and all azimuths, or
 * over the band's half toward (phi 0) or away from (phi pi) the sun. */
static double band_mean(const ad_solution *s, int b, int half)
{
    const gauss_rule *q = gauss_legendre_cached(NODES);
    const int A = 32;
    double sum = 0.0;
    for (int j = 0; j < NODES; j++)
        for (int a = 0; a < A; a++) {
            double phi = half < 0 ? 2.0 * FM_PI * (a + 0.5) / A : FM_PI * ((a + 0.5) / A - 0.5) + half * FM_PI;
            sum += 0.5 * q->w[j] * ad_radiance_bottom(s, b * NODES + j, phi) / A;
        }
    return sum;
}

static void overcast_deck_matches_adding_doubling(void **state)
{
    (void)state;
    char *path;
    fm_sky *sky = plane_sky("stratus", 30.0, 1.0, 1.0, 0.0, 0.0, &path);
    double mu[2 * NODES];
    ad_solution s = deck_reference(sky, 30.0, mu);
    double zenith = band_mean(&s, 0, -1), horizon = band_mean(&s, 1, -1);
    double L1 = ad_radiance_bottom(&s, NODES - 1, FM_PI / 2), L0 = ad_radiance_bottom(&s, NODES, FM_PI / 2);
    print_message("adding-doubling: L(mu %.3f) / L(mu %.3f) = %.3f (CIE overcast: %.3f); zenith cap / horizon band "
                  "%.3f (CIE %.3f)\n",
                  mu[NODES - 1], mu[NODES], L1 / L0, (1.0 + 2.0 * mu[NODES - 1]) / (1.0 + 2.0 * mu[NODES]),
                  zenith / horizon, (1.0 + (1.0 + ZENITH_CAP)) / (1.0 + HORIZON_BAND));
    /* the physics: a few times brighter overhead, as measured overcast skies and CIE's 3:1 */
    assert_true(L1 / L0 > 2.0 && L1 / L0 < 3.5);
    check_rel(band_mean(&s, 1, 0), band_mean(&s, 1, 1), 0.005, "adding-doubling: horizon toward / away from the sun");

    dome d = sample_dome(sky, paths(240000), 11);
    double mu0 = sin(SUN_ELEVATION * FM_DEG), se;
    check_within(d.E, d.E_se, mu0 * s.flux_down_diffuse, "tau 30 stratus: diffuse irradiance at the ground");
    double q = ratio(d.band[0], d.band_se[0], d.band[1], d.band_se[1], &se);
    check_within(q, se, zenith / horizon, "tau 30 stratus: zenith cap / horizon band");
    q = ratio(d.half[0], d.half_se[0], d.half[1], d.half_se[1], &se);
    check_within(q, se, 1.0, "tau 30 stratus: sky toward / away from the sun's azimuth");
    ad_free(&s);
    drop(sky, path);
}

/* ---- the Overcast preset's deck in the real atmosphere ---------------------------------------- */

static void overcast_sky_in_colour(void **state)
{
    (void)state;
    fm_sky_params p = fm_sky_params_default(); /* the rural aerosols, U.S. Standard air */
    p.clouds = "stratus";                      /* presets/clouds/stratus.json: 0.5-1.0 km, tau 30 */
    p.sun_elevation_deg = SUN_ELEVATION;
    p.sun_azimuth_deg = 180.0;
    fm_sky *sky = test_sky(&p);
    dome d = sample_dome(sky, paths(24000), 21);
    double h = SUN_ELEVATION * FM_DEG, krochmann = 7.0 * FM_PI / 9.0 * 1000.0 * (8.6 * sin(h) + 0.123), se;
    print_message("global horizontal illuminance at sun %.0f: %.0f +- %.0f lx (Krochmann & Seidl's overcast sky: "
                  "%.0f lx)\n",
                  SUN_ELEVATION, d.E, d.E_se, krochmann);
    assert_true(d.E > 0.5 * krochmann && d.E < 2.0 * krochmann);
    double q = ratio(d.band[0], d.band_se[0], d.band[1], d.band_se[1], &se);
    print_message("zenith cap / horizon band luminance %.2f +- %.2f (CIE overcast: %.2f)\n", q, se,
                  (2.0 + ZENITH_CAP) / (1.0 + HORIZON_BAND));
    assert_true(q > 1.6 && q < 3.5);
    q = ratio(d.half[0], d.half_se[0], d.half[1], d.half_se[1], &se);
    check_within(q, se, 1.0, "overcast: luminance toward / away from the sun's azimuth");
    fm_sky_destroy(sky);
}

/* ---- fog with the observer inside -------------------------------------------------------------- */

static void fog_with_the_observer_inside(void **state)
{
    (void)state;
    const double visibility = 200.0, depth = 200.0, tau = 3.912 / visibility * depth;
    char *path;
    fm_sky *sky = plane_sky(NULL, 0.0, FM_CLOUD_BASE_FROM_FILE, 0.0, visibility, 100.0, &path); /* presets/clouds/fog.json: 0-200 m */
    double mu[2 * NODES];
    ad_solution s = deck_reference(sky, tau, mu);
    const double mu0 = sin(SUN_ELEVATION * FM_DEG);
    double net_bottom = mu0 * (1.0 - ALBEDO) * (s.flux_down_direct + s.flux_down_diffuse);
    const int N = paths(600000);
    dome down = sample_dome(sky, N, 31);
    /* looking down: the same sampler with the observer's frame flipped (z -> -z) */
    path_context all = sky_path_context(sky, 1, 0);
    moments up = {0};
    for (int i = 0; i < N; i++) {
        rng r = rng_for(32, 0, (uint64_t)i);
        double m = rng_uniform(&r), phi = 2.0 * FM_PI * rng_uniform(&r), sn = sqrt(1.0 - m * m);
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(&all, sky->observer, v3(sn * sin(phi), sn * cos(phi), -m), 0, &r, L);
        add(&up, 2.0 * FM_PI * L[0] * m);
    }
    double up_se, E_up = mean_of(&up, &up_se);
    fm_sun_light sun;
    fm_sky_sun_light(sky, &sun);
    double net = down.E - E_up + sun.horizontal_irradiance[0];
    print_message("fog tau %.2f, observer at 100 m: down %.4f, up %.4f, direct %.4f\n", tau, down.E, E_up,
                  sun.horizontal_irradiance[0]);
    check_within(net, sqrt(down.E_se * down.E_se + up_se * up_se), net_bottom,
                 "fog, observer inside: net downward flux against the bottom's");
    double se, q = ratio(down.half[0], down.half_se[0], down.half[1], down.half_se[1], &se);
    print_message("fog: sky toward / away from the sun's azimuth %.3f +- %.3f\n", q, se);
    assert_true(q > 1.0 + 3.0 * se); /* inside the fog the sun's side is brighter: its forward peak */
    ad_free(&s);
    drop(sky, path);
}

int main(int argc, char **argv)
{
    if (argc > 1) /* one check by name (bench/overcast.sh) */
        cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(overcast_deck_matches_adding_doubling),
        cmocka_unit_test(overcast_sky_in_colour),
        cmocka_unit_test(fog_with_the_observer_inside),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

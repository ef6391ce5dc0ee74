/* Twilight: the sun below the horizon, the Earth's shadow over the observer.
 *
 *  - shadow geometry: single scattering along view rays that cross the shadow into the sunlit air
 *    (sun -4 to -10 degrees, from the ground and from 20 km) against an independent reference:
 *    Simpson's rule along the ray (4000 steps crowded at the observer) with exact columns for the
 *    view and, at every point, the disk-integrated sun transmittance with the Earth's occlusion
 *    integrated along each chord ray (no tables).  Both the fast path's quadrature and the
 *    along-segment sunlight estimator of the path tracer (sunlit_segment.h: umbra left out in
 *    closed form, importance-sampled sunlit part) must match within 1%;
 *  - the along-segment estimator against the point estimate it replaces: the same second-order
 *    radiance at the zenith within the noise, and a far smaller noise; likewise by day on rising
 *    segments, for a low sun behind thick haze;
 *  - deep twilight's guided flights (shadow_flight.h) against delta tracking, which they replace:
 *    the same orders >= 2 in three directions within the noise, and less noise per path; its
 *    light-led Russian roulette against the plain one, the same within the noise; the sky guide
 *    with its light of order 2 against a guide of single scattering alone, the same within the
 *    noise and less noise per path; the first vertices placed partly by the light against those
 *    placed by scattering x transmittance alone, the same within the noise;
 *  - the sky guide at vertices between its levels: its density integrates to 1 and its samples
 *    follow it (chi-square); its levels laid over a vertex's sky with the horizons lined up against
 *    by elevation alone, the same within the noise and less noise per path; heavy paths split
 *    into copies against whole ones, the same within the noise and less noise per path; in urban
 *    haze the preview's split weight at a vertex against the final's, the same within the noise
 *    and fewer copies;
 *  - zenith luminance falls monotonically as the sun goes from +10 to -10 degrees, every one-degree
 *    step by more than four standard errors of the difference;
 *  - the horizontal illuminance of a clear evening against the AMS Glossary of Meteorology;
 *  - the map at sun -18 is noise-free at the default quality (below). */
#include "check.h"
#include "seed_noise.h"

#include "atmosphere/optical_depth.h"
#include "base/rng.h"
#include "base/units.h"
#include "phase/phase.h"
#include "render/quality.h"
#include "spectrum/spectral_grid.h"
#include "transport/path.h"
#include "transport/single_scatter.h"
#include "transport/shadow_flight.h"
#include "transport/sky_guide_build.h"
#include "transport/sky_path.h"
#include "transport/sun_frame.h"
#include "transport/sunlit_segment.h"
#include "transport/twilight.h"

#include <math.h>
#include <stdlib.h>

typedef struct source_ctx {
    const fm_sky *sky;
    double cos_theta;
} source_ctx;

/* sum_c sigma_s,c p_c E0 Tbar at x, Tbar integrated along the chord rays (sun_transmittance_direct,
 * no tables) */
static double single_scattering_source(void *p, vec3 x)
{
    const source_ctx *c = p;
    const atmosphere *a = &c->sky->atm;
    double r = v3_length(x), tbar[1], n[FM_MAX_SPECIES], source = 0.0;
    sun_transmittance_direct(a, NULL, &c->sky->sun, r, v3_dot(x, c->sky->sun_dir) / r, tbar, NULL);
    atmosphere_densities(a, r, n);
    for (int s = 0; s < a->scattering_count; s++)
        source += a->species[s].sigma_s[0] * n[s] * phase_evaluate(&a->species[s].phase, 0, c->cos_theta);
    return source * a->grid.solar_irradiance[0] * tbar[0];
}

static void shadow_geometry(void **state)
{
    /* sun elevation, observer altitude (m), view elevation and azimuth from the sun (deg); rural
     * aerosols (1) or none (0) */
    const double cases[][5] = {{-4, 0, 5, 0, 0},  {-6, 0, 3, 0, 0},    {-10, 0, 2, 0, 0},    {-10, 0, 10, 0, 0},
                               {-6, 0, 90, 0, 0}, {-4, 0, 20, 180, 0}, {-10, 20000, -3, 0, 0}, {-4, 0, 5, 0, 1},
                               {-6, 0, 3, 0, 1},  {-10, 0, 2, 0, 1},   {-6, 0, 90, 0, 1},    {-10, 20000, -3, 0, 1}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fm_sky_params p = test_params(cases[i][0], 550.0);
        if (cases[i][4] > 0.0)
            p.biome = "rural";
        p.sun_azimuth_deg = 180.0;
        p.observer_altitude_m = cases[i][1];
        fm_sky *sky = test_sky(&p);
        path_context one = sky_path_context(sky, 1, 1);
        vec3 d = direction_from_elevation_azimuth(cases[i][2] * FM_DEG, (180.0 + cases[i][3]) * FM_DEG);
        source_ctx ctx = {sky, v3_dot(d, sky->sun_dir)};
        double ref = test_view_ray_integral(sky, d, 4000, single_scattering_source, &ctx, NULL, NULL);
        double quad[1] = {0};
        single_scatter_radiance(&one, sky->observer, d, quad);
        /* the along-segment estimator from the observer: L1 itself */
        ray_segment seg;
        ray_segment_init(&seg, &sky->atm, sky->observer, d);
        double u0 = seg.t_end, u1 = seg.t_end;
        int umbra = segment_umbra(&one, &seg, &u0, &u1);
        const int N = 160000;
        double sum = 0.0, sum2 = 0.0;
        for (int j = 0; j < N; j++) {
            rng r = rng_for(5, i, (uint64_t)j);
            double S[1] = {0};
            segment_sunlight(&one, &seg, u0, u1, &r, S);
            sum += S[0];
            sum2 += S[0] * S[0];
        }
        double mean = sum / N, se = sqrt(fmax(0.0, sum2 / N - mean * mean) / N);
        print_message("%s, sun %g, from %g m, view (%g, %g): reference %.5e, quadrature %.5e (%+.2f%%), along the "
                      "segment %.5e +- %.2f%% (%+.2f%%), umbra %s [%.0f, %.0f] km\n",
                      cases[i][4] > 0.0 ? "rural" : "molecules", cases[i][0], cases[i][1], cases[i][2], cases[i][3], ref, quad[0], 100.0 * (quad[0] / ref - 1.0),
                      mean, 100.0 * se / mean, 100.0 * (mean / ref - 1.0), umbra ? "yes" : "no", u0 / FM_KM,
                      u1 / FM_KM);
        assert_true(ref > 0.0);
        check_rel(quad[0], ref, 1e-2, "twilight single scattering: quadrature vs reference");
        assert_true(se < 2.5e-3 * mean);
        check_rel(mean, ref, 1e-2, "twilight single scattering: along-segment estimator vs reference");
        fm_sky_destroy(sky);
    }
}

static double luminance(const fm_sky *sky, const double *L)
{
    double xyz[3];
    spectral_grid_to_xyz(&sky->atm.grid, L, xyz);
    return xyz[1];
}

/* Orders >= 2 toward d from the observer (the fast path's table estimate): mean luminance-weighted
 * radiance and its standard error. */
static double multiple_scattering(const fm_sky *sky, const path_context *pc, vec3 d, int N, uint64_t item, double *se)
{
    double L[FM_MAX_WAVELENGTHS] = {0};
    node_moments m = {0};
    table_node_paths(sky, pc, d, N, 17, item, 0, L, &m, NULL, NULL);
    double mean = luminance(sky, L) / N;
    *se = sqrt(fmax(0.0, m.yy / N - mean * mean) / N);
    return mean;
}

/* The same radiance toward d by two estimators (n_a and n_b paths on the streams of item_a and
 * item_b): their means, standard errors and the z-score of their difference. */
typedef struct estimator_pair {
    double m_a, se_a, m_b, se_b, z;
} estimator_pair;

static estimator_pair compare_estimators(const fm_sky *sky, const path_context *a, int n_a, const path_context *b,
                                         int n_b, vec3 d, uint64_t item_a, uint64_t item_b)
{
    estimator_pair e;
    e.m_a = multiple_scattering(sky, a, d, n_a, item_a, &e.se_a);
    e.m_b = multiple_scattering(sky, b, d, n_b, item_b, &e.se_b);
    e.z = (e.m_b - e.m_a) / sqrt(e.se_a * e.se_a + e.se_b * e.se_b);
    return e;
}

/* Zenith luminance (single scattering by quadrature + orders >= 2 by the renderer's estimator, default
 * rural sky) from +10 to -10 degrees in 1-degree steps: each step down must lower it by more than four
 * standard errors of the difference. */
static void zenith_falls_monotonically(void **state)
{
    const vec3 zenith = v3(0.0, 0.0, 1.0);
    double prev = 0.0, prev_se = 0.0, worst_margin = INFINITY;
    for (int e = 10; e >= -10; e--) {
        fm_sky_params p = fm_sky_params_default();
        p.sun_elevation_deg = e;
        fm_sky *sky = test_sky(&p);
        twilight_sampling *guide;
        assert_int_equal(twilight_sampling_create(sky, SKY_GUIDE_MAX_OFFSETS, NULL, 2, NULL, &guide), FM_OK);
        assert_true((guide != NULL) == (e < 0));
        path_context one = sky_path_context(sky, 1, 1), many = twilight_path_context(sky, guide, 2, 0);
        many.skip_ground_first = 1;
        double L1[FM_MAX_WAVELENGTHS] = {0}, se;
        single_scatter_radiance(&one, sky->observer, zenith, L1);
        double ms = multiple_scattering(sky, &many, zenith, 20000, (uint64_t)(e + 100), &se);
        double y = luminance(sky, L1) + ms;
        if (e < 10) {
            double margin = (prev - y) / sqrt(prev_se * prev_se + se * se);
            worst_margin = fmin(worst_margin, margin);
            print_message("sun %+3d: zenith %.4e cd/m^2 (multiple scattering %.0f%% +- %.2f%%), %.3f of the step above, "
                          "drop %.0f sigma\n",
                          e, 683.0 * y, 100.0 * ms / y, 100.0 * se / y, y / prev, margin);
            assert_true(margin > 4.0);
        }
        prev = y;
        prev_se = se;
        free(guide);
        fm_sky_destroy(sky);
    }
    print_message("smallest drop: %.1f standard errors\n", worst_margin);
}

/* The along-segment sunlight against the point estimate at the next collision that it replaces:
 * orders >= 2 toward the zenith, sun 3 degrees down, rural.  Point estimates only; along the segment
 * where it enters the umbra (the daytime setting); and the whole twilight estimator (sky guide,
 * every segment along its length, stratified first vertices).  The same mean within four combined
 * standard errors, and the twilight estimator at least three times less noisy per path. */
static void along_segment_matches_point_estimate(void **state)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = -3.0;
    fm_sky *sky = test_sky(&p);
    twilight_sampling *guide;
    assert_int_equal(twilight_sampling_create(sky, SKY_GUIDE_MAX_OFFSETS, NULL, 2, NULL, &guide), FM_OK);
    assert_non_null(guide);
    const vec3 zenith = v3(0.0, 0.0, 1.0);
    path_context point = sky_path_context(sky, 2, 0), along = point, twilight = twilight_path_context(sky, guide, 2, 0);
    point.segment_sunlight = SEGMENT_SUNLIGHT_NONE;
    point.skip_ground_first = along.skip_ground_first = twilight.skip_ground_first = 1;
    const int n_point = 400000, n_along = 100000, n_twilight = 50000;
    double se_point, se_along, se_twilight;
    double m_point = multiple_scattering(sky, &point, zenith, n_point, 1, &se_point);
    double m_along = multiple_scattering(sky, &along, zenith, n_along, 2, &se_along);
    double m_twilight = multiple_scattering(sky, &twilight, zenith, n_twilight, 3, &se_twilight);
    double z_along = (m_along - m_point) / sqrt(se_point * se_point + se_along * se_along);
    double z_twilight = (m_twilight - m_point) / sqrt(se_point * se_point + se_twilight * se_twilight);
    double per_path = se_point * sqrt(n_point);
    print_message("point estimates %.5e +- %.2f%%; along the segment in the umbra %.5e +- %.2f%% (%+.1f sigma, noise "
                  "per path / %.1f); twilight estimator %.5e +- %.2f%% (%+.1f sigma, noise per path / %.1f)\n",
                  m_point, 100.0 * se_point / m_point, m_along, 100.0 * se_along / m_along, z_along,
                  per_path / (se_along * sqrt(n_along)), m_twilight, 100.0 * se_twilight / m_twilight, z_twilight,
                  per_path / (se_twilight * sqrt(n_twilight)));
    assert_true(fabs(z_along) < 4.0);
    assert_true(fabs(z_twilight) < 4.0);
    assert_true(per_path / (se_twilight * sqrt(n_twilight)) > 3.0);
    free(guide);
    fm_sky_destroy(sky);
}

/* By day with a low sun behind thick haze the table's paths take every rising segment's sunlight
 * along it (SEGMENT_SUNLIGHT_RISING, render.c): urban sunset (sun 2, turbidity 2), orders >= 2 from
 * stratified first vertices, toward the zenith and 5 degrees up 90 degrees from the sun, against the
 * point estimates of the daytime setting.  The same mean within four combined standard errors, and
 * the noise per path lower in both (measured 1.5-1.8 times). */
static void rising_segments_match_point_estimate(void **state)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = 2.0;
    p.sun_azimuth_deg = 0.0;
    p.biome = "urban";
    p.turbidity = 2.0;
    fm_sky *sky = test_sky(&p);
    path_context point = sky_path_context(sky, 2, 0), rising = point;
    rising.segment_sunlight = SEGMENT_SUNLIGHT_RISING;
    point.skip_ground_first = rising.skip_ground_first = 1;
    const double views[][2] = {{90.0, 0.0}, {5.0, 90.0}};
    const int n_point = 160000, n_rising = 60000;
    for (int i = 0; i < 2; i++) {
        vec3 d = direction_from_elevation_azimuth(views[i][0] * FM_DEG, views[i][1] * FM_DEG);
        estimator_pair e =
            compare_estimators(sky, &point, n_point, &rising, n_rising, d, 30 + (uint64_t)i, 40 + (uint64_t)i);
        double gain = (e.se_a * sqrt(n_point)) / (e.se_b * sqrt(n_rising));
        print_message("view %.0f deg up, %.0f deg from the sun: point estimates %.5e +- %.2f%%, rising segments along "
                      "%.5e +- %.2f%% (%+.1f sigma), noise per path / %.2f\n",
                      views[i][0], views[i][1], e.m_a, 100.0 * e.se_a / e.m_a, e.m_b, 100.0 * e.se_b / e.m_b, e.z,
                      gain);
        assert_true(fabs(e.z) < 4.0);
        assert_true(gain > 1.2);
    }
    fm_sky_destroy(sky);
}

/* The default rural sky with the sun sun_deg below the horizon at azimuth 0, in deep twilight, and
 * its twilight sampling. */
static twilight_sampling *deep_twilight(double sun_deg, fm_sky **sky)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = sun_deg;
    p.sun_azimuth_deg = 0.0;
    *sky = test_sky(&p);
    twilight_sampling *tw;
    assert_int_equal(twilight_sampling_create(*sky, SKY_GUIDE_MAX_OFFSETS, NULL, 2, NULL, &tw), FM_OK);
    assert_non_null(tw);
    assert_true(tw->deep);
    return tw;
}

/* Orders >= 2 as the fast path's table nodes take them with tw's sampling (a path whose first
 * interaction is the ground is left to single scattering's table). */
static path_context node_context(const fm_sky *sky, const twilight_sampling *tw)
{
    path_context pc = twilight_path_context(sky, tw, 2, 0);
    pc.skip_ground_first = 1;
    return pc;
}

/* Deep twilight's comparisons look toward the zenith, 10 degrees up toward the sun and 30 degrees
 * up away from it (elevation, azimuth in degrees). */
static const double views[][2] = {{90.0, 0.0}, {10.0, 0.0}, {30.0, 180.0}};

/* One estimator a against another b (n_a and n_b paths, the streams of items item + i and item + 10
 * + i) at sun sun_deg in the n views (elevation, azimuth in degrees), each named for the messages:
 * asserts every difference within four combined standard errors and returns b's relative variance
 * per path over a's, both summed over the views relative to a's means. */
static double compare_in(const fm_sky *sky, double sun_deg, const double (*view)[2], int n, const char *name_a,
                         const path_context *a, int n_a, const char *name_b, const path_context *b, int n_b,
                         uint64_t item)
{
    double var_a = 0.0, var_b = 0.0;
    for (int i = 0; i < n; i++) {
        vec3 d = direction_from_elevation_azimuth(view[i][0] * FM_DEG, view[i][1] * FM_DEG);
        estimator_pair e = compare_estimators(sky, a, n_a, b, n_b, d, item + (uint64_t)i, item + 10 + (uint64_t)i);
        var_a += e.se_a * e.se_a * n_a / (e.m_a * e.m_a);
        var_b += e.se_b * e.se_b * n_b / (e.m_a * e.m_a);
        print_message("sun %g, view (%g, %g): %s %.5e +- %.2f%%, %s %.5e +- %.2f%% (%+.2f%%, %+.1f sigma)\n", sun_deg,
                      view[i][0], view[i][1], name_a, e.m_a, 100.0 * e.se_a / e.m_a, name_b, e.m_b,
                      100.0 * e.se_b / e.m_b, 100.0 * (e.m_b / e.m_a - 1.0), e.z);
        assert_true(fabs(e.z) < 4.0);
    }
    print_message("relative noise per path: %s %.2f, %s %.2f\n", name_a, sqrt(var_a / n), name_b, sqrt(var_b / n));
    return var_b / var_a;
}

/* compare_in in the three views above. */
static double compare_in_views(const fm_sky *sky, double sun_deg, const char *name_a, const path_context *a, int n_a,
                               const char *name_b, const path_context *b, int n_b, uint64_t item)
{
    return compare_in(sky, sun_deg, views, 3, name_a, a, n_a, name_b, b, n_b, item);
}

/* Sun 9 degrees down, rural: orders >= 2 with the guided flights against the same estimator with
 * delta tracking (everything else equal), toward the zenith, 10 degrees up toward the sun and 30
 * degrees up away from it.  Within four combined standard errors in each, and the guided flights'
 * noise per path lower in all three together.  A density whose pdf or weights were off (a cell's
 * length, the ground's probability, a wavelength's transmittance) would move the mean by more. */
static void shadow_flights_match_delta_tracking(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-9.0, &sky);
    path_context guided = node_context(sky, tw), tracked = guided;
    tracked.shadow_flights = NULL;
    assert_true(compare_in_views(sky, -9.0, "delta tracking", &tracked, 120000, "guided flights", &guided, 60000, 10) <
                1.0);
    free(tw);
    fm_sky_destroy(sky);
}

/* Sun 14 degrees down, rural: orders >= 2 with deep twilight's light-led roulette (path.c) against
 * the plain roulette on the weight alone (everything else equal), in the three directions above.
 * Within four combined standard errors in each: a roulette changes only the noise, and one whose
 * survivors were weighted wrong would move the mean.  The light it is led by: above the observer,
 * single scattering is darker than the second order in the shadow (measured at the ground: I 12
 * times below the ambient; at sun -18 3700 times) and brighter in the sunlit air overhead (100 km:
 * 26 times above it); the bounds are 5 and 10 times. */
static void light_led_roulette_matches_the_plain_one(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-14.0, &sky);
    const shadow_flight_table *t = &tw->flights;
    const double R = sky->atm.bottom_radius_m, mu_s = sin(t->sun0);
    print_message("sun -14 above the observer: ground I %.3e ambient %.3e, 100 km I %.3e ambient %.3e\n",
                  shadow_flight_light(t, R, mu_s), t->ambient[0], shadow_flight_light(t, R + 100e3, mu_s),
                  t->ambient[SHADOW_FLIGHT_LEVELS - 1]);
    assert_true(t->ambient[0] > 5.0 * shadow_flight_light(t, R, mu_s));
    assert_true(shadow_flight_light(t, R + 100e3, mu_s) > 10.0 * t->ambient[SHADOW_FLIGHT_LEVELS - 1]);
    path_context led = node_context(sky, tw), plain = led;
    assert_true(led.light_led_roulette);
    plain.light_led_roulette = 0;
    compare_in_views(sky, -14.0, "plain roulette", &plain, 40000, "light-led", &led, 40000, 50);
    free(tw);
    fm_sky_destroy(sky);
}

/* Sun 18 degrees down, rural: orders >= 2 with the sky guide as rendered (single scattering and the
 * light of order 2, sky_guide.h) against the same renderer with a guide of single scattering alone,
 * in the three directions above.  Within four combined standard errors in each (a density changes
 * only the noise; one whose pdf disagreed with its samples would move the mean), and the noise per
 * path lower in the three together (these streams, with heavy paths split: 6.00 for single
 * scattering alone, 3.56 with the order 2; with the guide's horizons lined up and the light-led
 * roulette's floor, before the splitting: 24.3 and 4.3; with the
 * first vertices led by the light, before those two, 21.7 and 7.4; before that change 14.1 and
 * 5.6, and four other sets 8.5-10.0 and 5.6-7.4). */
static void order2_guide_matches_single_scattering_guide(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-18.0, &sky);
    twilight_sampling *single_only = malloc(sizeof *single_only);
    assert_non_null(single_only);
    *single_only = *tw;
    path_context single = sky_path_context(sky, 1, 1);
    int usable;
    assert_int_equal(sky_guide_build(&single_only->guide, &single, sky->observer, SKY_GUIDE_MAX_OFFSETS, 2, NULL, NULL, 0,
                                     NULL, &usable),
                     FM_OK);
    assert_true(usable);
    path_context a = node_context(sky, single_only), b = node_context(sky, tw);
    assert_true(compare_in_views(sky, -18.0, "single-scattering guide", &a, 40000, "with order 2", &b, 40000, 70) <
                1.0);
    free(single_only);
    free(tw);
    fm_sky_destroy(sky);
}

/* The sky guide at vertices between its levels (sun -18, rural, all offsets): its density
 * integrates to 1 over the vertex's sphere (midpoint rule, 24000 elevations x the 36 columns'
 * midpoints, within 0.5%), and 60000 directions drawn from it fall into bins of elevation from the
 * vertex's horizon (which its cells crowd: 0.3, 1, 3, 10 and 30 degrees either side) x azimuth
 * from the sun (30, 90, 180 degrees either side) as the density says (chi-square over the bins
 * with 5 or more expected, below 80, its 0.9999 quantile for 40 degrees of freedom; a sampler that
 * put the level's horizon on the vertex's without the density doing so fails it).  The vertices
 * lie 0.7 to 38.5 km up (the levels: 0, 4, 9, 15, 22, 32 and 45 km) and 0 to 10 degrees of arc
 * toward the sun. */
static void guide_density_matches_its_samples(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-18.0, &sky);
    const sky_guide *g = &tw->guide;
    const double R = sky->atm.bottom_radius_m, vertices[][2] = {{0.7, 0.0}, {6.5, 3.0}, {27.0, 0.0},
                                                                {38.5, 3.0}, {12.0, 10.0}, {38.5, 10.0}};
    const double edges_deg[] = {-90.0, -30.0, -10.0, -3.0, -1.0, -0.3, 0.0, 0.3, 1.0, 3.0, 10.0, 30.0, 90.0};
    enum { E_BINS = 12, A_BINS = 3, STEPS = 24000, COLS = 36, DRAWS = 60000 };
    const double a_edges_deg[] = {0.0, 30.0, 90.0, 180.0};
    sun_frame observer = sun_frame_at(sky->observer, sky->sun_dir);
    for (int v = 0; v < 6; v++) {
        double r = R + vertices[v][0] * FM_KM, eh = -acos(R / r);
        vec3 x = sun_frame_toward_sun(&observer, vertices[v][1] * FM_DEG, r);
        sun_frame f = sun_frame_at(x, sky->sun_dir);
        double expected[E_BINS][A_BINS] = {{0}}, total = 0.0;
        for (int i = 0; i < STEPS; i++) {
            double e = -0.5 * FM_PI + FM_PI * (i + 0.5) / STEPS, de = FM_PI / STEPS;
            int be = 0;
            while (be < E_BINS - 1 && e > eh + edges_deg[be + 1] * FM_DEG)
                be++;
            for (int c = 0; c < COLS; c++) {
                double phi = 2.0 * FM_PI * (c + 0.5) / COLS, az = fmin(phi, 2.0 * FM_PI - phi) / FM_DEG;
                double mass = sky_guide_pdf(g, x, sky->sun_dir, sun_frame_direction(&f, sin(e), phi)) * cos(e) * de *
                              2.0 * FM_PI / COLS;
                expected[be][az < 30.0 ? 0 : az < 90.0 ? 1 : 2] += mass;
                total += mass;
            }
        }
        double count[E_BINS][A_BINS] = {{0}};
        for (int n = 0; n < DRAWS; n++) {
            rng rn = rng_for(17, (uint64_t)v, (uint64_t)n);
            double u1 = rng_uniform(&rn), u2 = rng_uniform(&rn), u3 = rng_uniform(&rn);
            vec3 d = sky_guide_sample(g, x, sky->sun_dir, u1, u2, u3);
            double e = asin(clamp_cosine(v3_dot(d, f.up)));
            double az = fabs(atan2(v3_dot(d, f.side), v3_dot(d, f.sun_h))) / FM_DEG;
            int be = 0, ba = 0;
            while (be < E_BINS - 1 && e > eh + edges_deg[be + 1] * FM_DEG)
                be++;
            while (ba < A_BINS - 1 && az > a_edges_deg[ba + 1])
                ba++;
            count[be][ba] += 1.0;
        }
        double chi2 = 0.0;
        int bins = 0;
        for (int be = 0; be < E_BINS; be++)
            for (int ba = 0; ba < A_BINS; ba++) {
                double m = DRAWS * expected[be][ba] / total;
                if (m >= 5.0) {
                    chi2 += (count[be][ba] - m) * (count[be][ba] - m) / m;
                    bins++;
                }
            }
        print_message("vertex %.1f km, %.0f deg toward the sun: density integral %.5f, chi-square %.1f over %d bins\n",
                      vertices[v][0], vertices[v][1], total, chi2, bins);
        assert_true(fabs(total - 1.0) < 5e-3);
        assert_true(chi2 < 80.0);
    }
    free(tw);
    fm_sky_destroy(sky);
}

/* Sun 18 degrees down, rural: orders >= 2 with the sky guide's levels laid over a vertex's sky with
 * the horizons lined up (sky_guide.h, as rendered) against by elevation alone, in the three
 * directions above: within four combined standard errors in each, and less noise per path in the
 * three together (these streams: 5.44 by elevation, 3.71 lined up; before the split of heavy
 * paths (path.c) 5.89 / 3.81, before the light-led roulette's floor 5.84 / 4.00, and five other sets 5.13 / 5.78, 5.37 / 5.00, 4.64 /
 * 4.27, 12.3 / 4.92 and 4.95 / 3.90: the tail that the alignment cuts is rare paths of great
 * weight, which one set of 40000 may or may not meet). */
static void aligned_guide_matches_unaligned(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-18.0, &sky);
    twilight_sampling *unaligned = malloc(sizeof *unaligned);
    assert_non_null(unaligned);
    *unaligned = *tw;
    unaligned->guide.align_horizons = 0;
    path_context a = node_context(sky, unaligned), b = node_context(sky, tw);
    assert_true(compare_in_views(sky, -18.0, "by elevation", &a, 40000, "horizons lined up", &b, 40000, 150) < 1.0);
    free(unaligned);
    free(tw);
    fm_sky_destroy(sky);
}

/* Sun 18 degrees down, rural: orders >= 2 with heavy paths split into copies (path.c, as rendered)
 * against whole paths (everything else equal), near the horizon, where the heavy paths are: half a
 * degree up 160 degrees from the sun, 3 degrees up at 100 and 1 degree up at 40.  Within four
 * combined standard errors in each (copies that did not share their path's weight exactly would
 * move the mean), and less noise per path in the three together (these streams: 7.13 whole, 5.22
 * split; five other sets 7.46 / 7.24, 8.27 / 4.72, 6.03 / 5.92, 13.3 / 4.76, 6.49 / 6.06; in the
 * three views above, higher up, these streams 3.65 / 3.94: there few paths grow heavy). */
static void split_paths_match_whole_ones(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-18.0, &sky);
    path_context split = node_context(sky, tw), whole = split;
    assert_true(split.split_heavy_paths);
    whole.split_heavy_paths = 0;
    const double low[][2] = {{0.5, 160.0}, {3.0, 100.0}, {1.0, 40.0}};
    assert_true(compare_in(sky, -18.0, low, 3, "whole", &whole, 40000, "split", &split, 40000, 170) < 1.0);
    free(tw);
    fm_sky_destroy(sky);
}

/* Urban haze at sun -20: the preview's (and so the live sky's) paths split at a vertex past weight x
 * lift 10 (quality.c), the final's past 3 (path.c).  The haze near the ground lies deep in the Earth's
 * shadow, a path's first light is small and the light-led lift large, so at 3 most vertices on the
 * way up split.  The preview's rule must leave the mean where it was, within three combined standard
 * errors in each view (near the horizon, where heavy paths are, and at the zenith; copies that did
 * not share their path's weight would move it), and make fewer copies: a split at weight x lift m
 * makes fewer than m / 10 copies instead of m / 3, so at most 3 / 10 as many (with margin, 0.4 of
 * them), and under 4 per path from the observer (measured: 9.58 at 3, 2.51 at 10). */
static void hazy_preview_splits_less(void **state)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = -20.0;
    p.sun_azimuth_deg = 0.0;
    p.biome = "urban";
    fm_sky *sky = test_sky(&p);
    twilight_sampling *tw;
    assert_int_equal(twilight_sampling_create(sky, 1, NULL, 2, NULL, &tw), FM_OK);
    assert_non_null(tw);
    path_context final = node_context(sky, tw), preview = final;
    assert_true(final.split_heavy_paths && final.vertex_split_weight == 0.0);
    preview.vertex_split_weight = render_quality_settings(FM_QUALITY_PREVIEW, 1.0).deep_vertex_split_weight;
    assert_true(preview.vertex_split_weight == 10.0);
    const double view[][2] = {{0.5, 160.0}, {3.0, 100.0}, {1.0, 40.0}, {90.0, 0.0}};
    for (int i = 0; i < 4; i++) {
        vec3 d = direction_from_elevation_azimuth(view[i][0] * FM_DEG, view[i][1] * FM_DEG);
        estimator_pair e =
            compare_estimators(sky, &final, 12000, &preview, 24000, d, 190 + (uint64_t)i, 200 + (uint64_t)i);
        print_message("urban, sun -20, view (%g, %g): split at 3 %.5e +- %.2f%%, at 10 %.5e +- %.2f%% (%+.2f%%, %+.1f "
                      "sigma)\n",
                      view[i][0], view[i][1], e.m_a, 100.0 * e.se_a / e.m_a, e.m_b, 100.0 * e.se_b / e.m_b,
                      100.0 * (e.m_b / e.m_a - 1.0), e.z);
        assert_true(fabs(e.z) < 3.0);
    }
    double L[FM_MAX_WAVELENGTHS] = {0}, copies[2] = {0.0, 0.0};
    const int n = 2000;
    for (int rule = 0; rule < 2; rule++)
        for (int i = 0; i < n; i++) {
            rng r = rng_for(4321, 5, (uint64_t)i);
            vec3 d = direction_from_elevation_azimuth((0.5 + (i % 16) * 5.5) * FM_DEG, 22.5 * (i % 16) * FM_DEG);
            copies[rule] += path_trace(rule ? &preview : &final, sky->observer, d, i % sky->atm.grid.count, &r, L);
        }
    print_message("urban, sun -20: copies per path %.2f split at 3, %.2f at 10\n", copies[0] / n, copies[1] / n);
    assert_true(copies[1] / n < 4.0);
    assert_true(copies[1] < 0.4 * copies[0]);
    free(tw);
    fm_sky_destroy(sky);
}

/* Night (sun below -21 degrees, twilight.c): heavy paths are not split.  There the light at a path's
 * first point is so small that nearly every vertex passes the split weight, and the copies, each
 * inheriting what is left of the budget, made an 8-pixel preview take 85 s CPU at sun -31.5 for a
 * sky of 2e-11 lux (docs/decisions/2026-12-06-night-paths.md).  Deep twilight above it splits. */
static void night_paths_are_not_split(void **state)
{
    const double suns[] = {-18.0, -20.5, -21.5, -31.5, -45.0};
    for (int i = 0; i < 5; i++) {
        fm_sky *sky;
        twilight_sampling *tw = deep_twilight(suns[i], &sky);
        assert_int_equal(node_context(sky, tw).split_heavy_paths, suns[i] > -21.0);
        free(tw);
        fm_sky_destroy(sky);
    }
}

/* A path and all its copies make at most 1024 copies together (path.c, SPLIT_TOTAL).  With the sun
 * 35 degrees down and splitting forced on, nearly every vertex passes the split weight (the light at
 * a path's first point is tiny), and with each copy inheriting what was left of its path's budget
 * the copies of copies multiplied (about 1500 per path: docs/decisions/2026-12-06-night-paths.md). */
static void split_copies_are_bounded_per_path(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-35.0, &sky);
    path_context pc = node_context(sky, tw);
    pc.split_heavy_paths = 1;
    double L[FM_MAX_WAVELENGTHS] = {0};
    int most = 0;
    double total = 0.0;
    for (int i = 0; i < 32; i++) {
        rng r = rng_for(1234, 77, (uint64_t)i);
        vec3 d = direction_from_elevation_azimuth((1.0 + (i % 8)) * FM_DEG, 90.0 * (i / 8) * FM_DEG);
        int copies = path_trace(&pc, sky->observer, d, i % sky->atm.grid.count, &r, L);
        most = copies > most ? copies : most;
        total += copies;
    }
    print_message("sun -35, split forced: %.1f copies per path, at most %d\n", total / 32.0, most);
    assert_true(most <= 1024);
    assert_true(most > 32); /* the paths do split at nearly every vertex, beyond one path's budget */
    free(tw);
    fm_sky_destroy(sky);
}

/* Sun 14 degrees down, rural: orders >= 2 with half the first vertices placed along the view ray by
 * the light there (view_ray_vertices.h, as rendered) against all of them by scattering x
 * transmittance alone (everything else equal), in the three directions above: within four combined
 * standard errors in each.  A vertex whose weight disagreed with its density would move the mean;
 * the gain is time, not noise per path. */
static void light_led_first_vertices_match_plain_ones(void **state)
{
    fm_sky *sky;
    twilight_sampling *tw = deep_twilight(-14.0, &sky);
    path_context led = node_context(sky, tw), plain = led;
    assert_true(led.first_vertex_light_share > 0.0);
    plain.first_vertex_light_share = 0.0;
    compare_in_views(sky, -14.0, "first vertices by scattering", &plain, 30000, "half by the light", &led, 30000, 90);
    free(tw);
    fm_sky_destroy(sky);
}

/* Horizontal illuminance (all of it scattered sunlight once the sun is down) of the default rural
 * sky against the American Meteorological Society's Glossary of Meteorology (entries "civil
 * twilight" and "astronomical twilight"): during a clear evening it falls to about 3.5-2 lux at sun
 * -6 degrees and to about 0.008 lux at -12; at -18 scattered sunlight gives less than starlight and
 * airglow, which with it make about 6e-4 lux.  Measured skies vary (aerosols, ozone, refraction,
 * which the model leaves out, and the glossary's values are rounded), so the bounds are a factor 2
 * about those values: what they check is the fall over four decades through the shadow's geometry
 * (measured: 5.16, 0.0115 and 2.1e-5 lux). */
static void illuminance_against_the_ams_glossary(void **state)
{
    const double cases[][3] = {{-6.0, 2.0 / 2.0, 3.5 * 2.0}, {-12.0, 0.008 / 2.0, 0.008 * 2.0}, {-18.0, 0.0, 6e-4}};
    for (int i = 0; i < 3; i++) {
        fm_sky_params p = fm_sky_params_default();
        p.sun_elevation_deg = cases[i][0];
        fm_sky *sky = test_sky(&p);
        fm_image *img = test_render(sky, 64, FM_QUALITY_PREVIEW, 2, 1, 0, 1.0, 0);
        double xyz[3];
        assert_int_equal(fm_image_diffuse_horizontal(img, xyz), 1);
        double lux = FM_LUMINOUS_EFFICACY * xyz[1];
        print_message("sun %+.0f: horizontal illuminance %.4g lux (bounds %.3g to %.3g)\n", cases[i][0], lux,
                      cases[i][1], cases[i][2]);
        assert_true(lux > cases[i][1] && lux < cases[i][2]);
        fm_image_destroy(img);
        fm_sky_destroy(sky);
    }
}

/* Two final 256 x 128 maps of sky (seeds 1 and 2, the sample scale given) and their noise as
 * bench/seed_noise.h measures it, displayed at the sidecar's suggested exposure (white under the
 * horizontal illuminance E shown as 1), which the Blender add-on sets: log2(683 pi / E).  Returns
 * that exposure; the maps are the caller's. */
static double two_seeds_noise(const fm_sky *sky, double scale, fm_image **a, fm_image **b, seed_noise *n)
{
    *a = test_render(sky, 256, FM_QUALITY_FINAL, 2, 1, 0, scale, 0);
    *b = test_render(sky, 256, FM_QUALITY_FINAL, 2, 2, 0, scale, 0);
    double xyz[3];
    assert_int_equal(fm_image_diffuse_horizontal(*a, xyz), 1);
    double ev = log2(FM_PI / xyz[1]);
    assert_int_equal(seed_noise_measure(*a, *b, ev, n), 0);
    return ev;
}

/* Deep twilight's map is noise-free at the default (final) quality: two maps of the default sky at sun
 * -18, 256 x 128, seeds 1 and 2, compared as bench/seed_noise.h says.  Noise-free means no grain (the
 * noise from one pixel to the next below 0.2%), and broad variations that the eye does not see: one
 * map's luminance within 2% (relative standard deviation), and the two maps as displayed at the
 * sidecar's suggested exposure a CIEDE2000 difference of less than 1 on average (the smallest difference seen
 * side by side is about 1) and less than 4.5 at the 99th percentile (the horizon's band).  Measured,
 * six pairs of seeds: grain 0.05-0.14%, luminance 1.19-1.59%, mean 0.65-0.81, p99 2.6-3.6; with the
 * quality's paths alone (a quarter of what final takes at -18): 0.19%, 3.0%, 0.96 and 6.0. */
static void deep_twilight_map_is_noise_free(void **state)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = -18.0;
    fm_sky *sky = test_sky(&p);
    fm_image *a, *b;
    seed_noise n;
    double ev = two_seeds_noise(sky, 1.0, &a, &b, &n);
    print_message("sun -18, final, EV %.2f: one map's luminance %.2f%%, grain %.3f%%, R/G %.2f%%, B/G %.2f%%; CIEDE2000 "
                  "between two seeds mean %.2f, p99 %.2f\n",
                  ev, 100.0 * n.luminance, 100.0 * n.grain, 100.0 * n.red_green, 100.0 * n.blue_green, n.de_mean,
                  n.de_p99);
    assert_true(n.grain < 0.002);
    assert_true(n.luminance < 0.02);
    assert_true(n.de_mean < 1.0);
    assert_true(n.de_p99 < 4.5);
    /* the default sky meets its noise with the paths of the first pass (render.c: twilight_extra_paths) */
    assert_int_equal(a->paths_per_node, 4096);
    assert_int_equal(b->paths_per_node, 4096);
    fm_image_destroy(a);
    fm_image_destroy(b);
    fm_sky_destroy(sky);
}

/* Hazy deep twilight takes the paths that its noise needs: urban air at turbidity 2, sun -18, whose
 * paths are noisier than the default sky's (render.c: twilight_extra_paths), at an eighth of the
 * final quality's paths to keep the test short (the noise aimed at grows as the square root of the
 * eighth, and the criterion of deep_twilight_map_is_noise_free with it: luminance within
 * 2% x sqrt(8)).  The second pass must have run (the first has 512 paths per node) and the maps must
 * meet the scaled criterion, which the first pass's paths alone miss.  Measured: 1224 and 1179 paths
 * per node, luminance 4.02% (bound 5.66%), R / G 5.09%, CIEDE2000 1.88 / 6.16; with the first pass
 * alone 6.08%, 7.22%, 2.59 / 8.38. */
static void hazy_deep_twilight_takes_the_paths_it_needs(void **state)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = -18.0;
    p.biome = "urban";
    p.turbidity = 2.0;
    fm_sky *sky = test_sky(&p);
    const double scale = 0.125;
    fm_image *a, *b;
    seed_noise n;
    two_seeds_noise(sky, scale, &a, &b, &n);
    print_message("urban T 2, sun -18, final x 1/8: paths per node %d and %d; one map's luminance %.2f%%, R/G %.2f%%, "
                  "B/G %.2f%%; CIEDE2000 between two seeds mean %.2f, p99 %.2f\n",
                  a->paths_per_node, b->paths_per_node, 100.0 * n.luminance, 100.0 * n.red_green,
                  100.0 * n.blue_green, n.de_mean, n.de_p99);
    assert_true(a->paths_per_node > 2 * 512 && b->paths_per_node > 2 * 512);
    assert_true(n.luminance < 0.02 * sqrt(1.0 / scale));
    fm_image_destroy(a);
    fm_image_destroy(b);
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shadow_geometry),
        cmocka_unit_test(along_segment_matches_point_estimate),
        cmocka_unit_test(rising_segments_match_point_estimate),
        cmocka_unit_test(shadow_flights_match_delta_tracking),
        cmocka_unit_test(order2_guide_matches_single_scattering_guide),
        cmocka_unit_test(guide_density_matches_its_samples),
        cmocka_unit_test(aligned_guide_matches_unaligned),
        cmocka_unit_test(light_led_roulette_matches_the_plain_one),
        cmocka_unit_test(split_paths_match_whole_ones),
        cmocka_unit_test(night_paths_are_not_split),
        cmocka_unit_test(split_copies_are_bounded_per_path),
        cmocka_unit_test(hazy_preview_splits_less),
        cmocka_unit_test(light_led_first_vertices_match_plain_ones),
        cmocka_unit_test(zenith_falls_monotonically),
        cmocka_unit_test(illuminance_against_the_ams_glossary),
        cmocka_unit_test(deep_twilight_map_is_noise_free),
        cmocka_unit_test(hazy_deep_twilight_takes_the_paths_it_needs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

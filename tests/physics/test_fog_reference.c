/* The reference estimator in twilight fog and under a twilight overcast (issue 48;
 * docs/decisions/2026-12-07-fog-reference.md): the twilight sampling that reference mode takes
 * (twilight_path_context) must agree with plain path tracing, with honest standard errors.
 * - segment_sunlight_in_a_deck: the sunlight along a segment from inside the stratus deck at sun -1
 *   (sunlit_segment.h, every segment's at twilight), the mean of 3000 estimates against the integral
 *   by quadrature with exact columns, within 3 % plus 4 standard errors.  Fails with the segment's
 *   transmittance from the column table's bilinear lookup through the deck (17-38 % dark).
 * - twilight_sampling_in_fog: fog of 200 m visibility, sun -1, 550 nm, two views; the twilight
 *   sampling's radiance against plain paths' within 2 % plus 3 standard errors, each standard error
 *   under 3 %.  Fails with the twilight guides kept at their shares in the fog (standard errors of
 *   11-53 %, the mean 40 % dark at one view).
 * - deep_twilight_in_fog: the same at sun -6 (deep twilight's sampling), 30 degrees up away from the
 *   sun, within 2 % plus 3 standard errors, the twilight sampling's under 3 %.  Fails with the
 *   shadow flights placing the vertices in the fog too (its standard error 7 %, 10 % dark).
 * - overcast_azimuths_in_twilight: under the stratus at sun -1, the twilight sampling's views 30
 *   degrees up toward and away from the sun (equal by diffusion) within 2 % plus 3 standard errors,
 *   each under 5 %.  Fails with either fault above.
 * About 35 s of CPU. */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/rng.h"
#include "base/units.h"
#include "render/render.h"
#include "transport/path_direction.h"
#include "transport/sky_path.h"
#include "transport/sunlit_segment.h"
#include "transport/twilight.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static fm_sky *twilight_sky(double sun_deg, double fog_visibility_m, const char *clouds)
{
    fm_sky_params p = fm_sky_params_default();
    p.fog_visibility_m = fog_visibility_m;
    p.clouds = clouds;
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = sun_deg;
    p.sun_azimuth_deg = 180.0;
    return test_sky(&p);
}

/* The integrand of sunlit_segment.h at distance t: T(x, x_t) sigma_s p E0 Tbar(x_t), the
 * transmittance from the exact column. */
static double segment_integrand(const fm_sky *sky, const ray_segment *seg, double t)
{
    const atmosphere *atm = &sky->atm;
    double r = ray_segment_radius(seg, t), r0 = v3_length(seg->origin);
    vec3 x = v3_madd(seg->origin, seg->dir, t);
    double tbar[FM_MAX_WAVELENGTHS], n[FM_MAX_SPECIES], p[FM_MAX_WAVELENGTHS], s[FM_MAX_WAVELENGTHS];
    double col[FM_MAX_SPECIES];
    sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, r, v3_dot(x, sky->sun_dir) / r, tbar);
    if (!(tbar[0] > 0.0))
        return 0.0;
    atmosphere_densities(atm, r, n);
    medium_phase(atm, n, v3_dot(seg->dir, sky->sun_dir), p, s);
    column_exact(atm, r0, seg->s0 / r0, t, col);
    return exp(-atmosphere_optical_depth(atm, col, 0)) * s[0] * p[0] * atm->grid.solar_irradiance[0] * tbar[0];
}

/* The integral over the segment by Simpson's rule in u, t = t_end u^3 (nodes crowd at the origin,
 * where the deck's transmittance falls fastest). */
static double segment_integral(const fm_sky *sky, const ray_segment *seg, int steps)
{
    double sum = 0.0;
    for (int i = 0; i <= steps; i++) {
        double u = (double)i / steps, t = seg->t_end * u * u * u, dt_du = 3.0 * seg->t_end * u * u;
        double w = i == 0 || i == steps ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += w * segment_integrand(sky, seg, t) * dt_du;
    }
    return sum / (3.0 * steps);
}

static void segment_sunlight_in_a_deck(void **state)
{
    (void)state;
    fm_sky *sky = twilight_sky(-1.0, 0.0, "stratus"); /* optical depth 30 at 0.5-1 km */
    path_context pc = sky_path_context(sky, 1, 0);
    pc.segment_sunlight = SEGMENT_SUNLIGHT_ALL;
    const vec3 up = v3_normalize(sky->observer);
    static const double cases[][3] = {{990, 5, 0}, {990, 12, 0}, {990, 30, 0}, {990, 60, 0}, {990, 30, 180}, {970, 30, 90}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const double z = cases[c][0], e = cases[c][1] * FM_DEG, phi = cases[c][2] * FM_DEG;
        ray_segment seg;
        ray_segment_init(&seg, &sky->atm, v3_scale(up, sky->atm.bottom_radius_m + z),
                         render_view_direction(sky, e, phi));
        double u0 = seg.t_end, u1 = seg.t_end;
        if (!segment_umbra(&pc, &seg, &u0, &u1))
            u0 = u1 = seg.t_end;
        const int N = 3000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < N; i++) {
            rng r = rng_for(5, c, (uint64_t)i);
            double S[FM_MAX_WAVELENGTHS] = {0};
            segment_sunlight(&pc, &seg, u0, u1, &r, S);
            sum += S[0];
            sum2 += S[0] * S[0];
        }
        const double mean = sum / N, se = sqrt(fmax(0.0, sum2 / N - mean * mean) / N);
        const double exact = segment_integral(sky, &seg, 6000);
        char what[96];
        snprintf(what, sizeof what, "segment from %.0f m, %.0f degrees up, %.0f from the sun (se %.2f %%)", z,
                 cases[c][1], cases[c][2], 100.0 * se / mean);
        print_message("%s: %.6g against %.6g (%+.2f %%)\n", what, mean, exact, 100.0 * (mean / exact - 1.0));
        assert_true(exact > 0.0);
        check_abs(mean, exact, 0.03 * exact + 4.0 * se, what);
    }
    fm_sky_destroy(sky);
}

/* The twilight sampling as reference mode takes it (render_twilight, twilight_path_context). */
typedef struct reference_sampling {
    render_job job;
    fm_render_params rp;
    twilight_sampling *tw;
    path_context pc;
} reference_sampling;

static void reference_sampling_init(reference_sampling *s, const fm_sky *sky)
{
    s->rp = fm_render_params_default();
    s->rp.quality = FM_QUALITY_REFERENCE;
    s->rp.width = 64;
    s->job = (render_job){.sky = sky, .params = &s->rp};
    fm_error err;
    assert_int_equal(render_start(&s->job, &err), FM_OK);
    assert_int_equal(render_twilight(&s->job, &s->tw, &err), FM_OK);
    assert_non_null(s->tw);
    s->pc = twilight_path_context(sky, s->tw, 1, 0);
}

static void reference_sampling_free(reference_sampling *s)
{
    free(s->tw);
    render_tables_free(&s->job);
    fm_image_destroy(s->job.img);
}

/* a and b within 2 % plus 3 standard errors of their difference */
static void check_agree(double a, double se_a, double b, double se_b, const char *what)
{
    print_message("%s: %.6g +- %.2f %% against %.6g +- %.2f %% (%+.2f %%)\n", what, a, 100.0 * se_a / a, b,
                  100.0 * se_b / b, 100.0 * (a / b - 1.0));
    check_abs(a, b, 0.02 * b + 3.0 * hypot(se_a, se_b), what);
}

static void twilight_sampling_in_fog(void **state)
{
    (void)state;
    fm_sky *sky = twilight_sky(-1.0, 200.0, NULL);
    reference_sampling ref;
    reference_sampling_init(&ref, sky);
    path_context plain = sky_path_context(sky, 1, 0);
    static const double views[][2] = {{30, 180}, {10, 0}};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        const vec3 d = render_view_direction(sky, views[i][0] * FM_DEG, views[i][1] * FM_DEG);
        double se_t, se_p;
        const double t = test_path_radiance(&ref.pc, sky->observer, d, 40000, 3, 10 + i, &se_t);
        const double p = test_path_radiance(&plain, sky->observer, d, 40000, 3, 20 + i, &se_p);
        char what[96];
        snprintf(what, sizeof what, "fog, sun -1, %.0f up, %.0f from the sun: twilight sampling / plain", views[i][0],
                 views[i][1]);
        check_agree(t, se_t, p, se_p, what);
        assert_true(se_t < 0.03 * t);
        assert_true(se_p < 0.03 * p);
    }
    reference_sampling_free(&ref);
    fm_sky_destroy(sky);
}

/* Deep twilight (sun -6): the shadow flights, the light-led roulette and the split paths, from the
 * fog's top up; the fog's own vertices by delta tracking. */
static void deep_twilight_in_fog(void **state)
{
    (void)state;
    fm_sky *sky = twilight_sky(-6.0, 200.0, NULL);
    reference_sampling ref;
    reference_sampling_init(&ref, sky);
    assert_non_null(ref.pc.shadow_flights);
    path_context plain = sky_path_context(sky, 1, 0);
    const vec3 d = render_view_direction(sky, 30.0 * FM_DEG, FM_PI);
    double se_t, se_p;
    const double t = test_path_radiance(&ref.pc, sky->observer, d, 16000, 3, 40, &se_t);
    const double p = test_path_radiance(&plain, sky->observer, d, 40000, 3, 41, &se_p);
    check_agree(t, se_t, p, se_p, "fog, sun -6, 30 up, 180 from the sun: twilight sampling / plain");
    assert_true(se_t < 0.03 * t);
    assert_true(se_p < 0.08 * p);
    reference_sampling_free(&ref);
    fm_sky_destroy(sky);
}

static void overcast_azimuths_in_twilight(void **state)
{
    (void)state;
    fm_sky *sky = twilight_sky(-1.0, 0.0, "stratus");
    reference_sampling ref;
    reference_sampling_init(&ref, sky);
    double L[2], se[2];
    for (int i = 0; i < 2; i++) {
        const vec3 d = render_view_direction(sky, 30.0 * FM_DEG, i * 180.0 * FM_DEG);
        L[i] = test_path_radiance(&ref.pc, sky->observer, d, 20000, 5, 30 + i, &se[i]);
    }
    check_agree(L[0], se[0], L[1], se[1], "stratus, sun -1, 30 up: toward the sun / away from it");
    for (int i = 0; i < 2; i++)
        assert_true(se[i] < 0.05 * L[i]);
    reference_sampling_free(&ref);
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(segment_sunlight_in_a_deck),
        cmocka_unit_test(twilight_sampling_in_fog),
        cmocka_unit_test(deep_twilight_in_fog),
        cmocka_unit_test(overcast_azimuths_in_twilight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

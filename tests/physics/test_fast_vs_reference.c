/* The fast path (radiance tables) against the reference mode (per-pixel path tracing, no tables),
 * on small maps of a noon sky, a sunset and a noon sky seen from eye height (2 m: the horizon dips
 * 0.045 degrees, a sliver of sky below the horizontal) and from 10 km, with aerosols (rural noon, urban
 * sunset at turbidity 2), and at twilight (rural, sun -4 degrees), at the default final quality.
 *
 * The reference maps (luminance and its standard error per pixel, 1024 to 4096 paths per pixel:
 * about 4 CPU-minutes in all) are stored in tests/data/fast_vs_reference/; FM_REGENERATE=1 renders
 * and writes them again (after a deliberate change of the physics).  Each run checks that the
 * reference mode still gives the stored map: 96 of its pixels, rendered afresh with 2048 paths and
 * other random numbers, must agree with the stored ones within their joint noise (mean z^2 < 1.5
 * and |mean z| < 0.45, 3.5 and 4.4 standard deviations of those means; every |z| < 5); so the
 * stored map stays what the reference mode renders today.  (With the Rayleigh cross section 2%
 * higher this check alone fails at noon, mean z^2 1.55, and the fast path fails its own checks in
 * five of the seven skies.)
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

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FAST_SEEDS 2
#define W 48
#define H 24
#define REFERENCE_SEED 11
#define SPOT_PIXELS 96
#define SPOT_PATHS 2048

/* 0 sky, 1 the rows at the horizon, 2 ground */
static int region_of(int y) { return y < H / 2 - 1 ? 0 : (y <= H / 2 ? 1 : 2); }

typedef struct reference_map {
    double y[W * H], se[W * H]; /* luminance (W m^-2 sr^-1) and its standard error */
} reference_map;

static void reference_path(char *path, size_t size, const char *name)
{
    snprintf(path, size, "%s/fast_vs_reference/%s.txt", FM_TEST_DATA_DIR, name);
}

static void write_reference(const char *name, const char *description, int paths, const fm_image *ref,
                            reference_map *map)
{
    char path[4096], tmp[4200];
    reference_path(path, sizeof path, name);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        fail_msg("cannot write %s", tmp);
    fprintf(f, "# The reference mode's map for tests/physics/test_fast_vs_reference.c, case %s: %s.\n", name,
            description);
    fprintf(f, "# %d x %d equirect, %d paths per pixel, seed %d; per pixel (row-major from the zenith row):\n", W,
            H, paths, REFERENCE_SEED);
    fprintf(f, "# CIE Y (W m^-2 sr^-1) and its standard error.  Regenerate: FM_REGENERATE=1 test_fast_vs_reference\n");
    fprintf(f, "%d %d\n", W, H);
    for (int i = 0; i < W * H; i++) {
        size_t c = (size_t)i * 3 + 1;
        map->y[i] = ref->pixels[c];
        map->se[i] = ref->std_error[c];
        fprintf(f, "%.9g %.9g\n", map->y[i], map->se[i]);
    }
    if (fclose(f) || rename(tmp, path))
        fail_msg("cannot write %s", path);
    print_message("wrote %s\n", path);
}

static void read_reference(const char *name, reference_map *map)
{
    char path[4096], line[512];
    reference_path(path, sizeof path, name);
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("cannot read %s (FM_REGENERATE=1 writes it)", path);
    int w = 0, h = 0, n = 0, header = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        if (!header) {
            header = sscanf(line, "%d %d", &w, &h) == 2;
            if (!header || w != W || h != H)
                fail_msg("%s: expected a %d x %d map, found '%s'", path, W, H, line);
        } else if (n >= W * H || sscanf(line, "%lf %lf", &map->y[n], &map->se[n]) != 2) {
            fail_msg("%s: bad or extra line %d: '%s'", path, n, line);
        } else {
            n++;
        }
    }
    fclose(f);
    if (n != W * H)
        fail_msg("%s: %d pixels, expected %d", path, n, W * H);
}

/* The reference mode today against the stored map, at SPOT_PIXELS pixels spread over the map. */
static void check_reference_still_holds(const fm_sky *sky, const reference_map *map)
{
    int x[SPOT_PIXELS], y[SPOT_PIXELS];
    for (int i = 0; i < SPOT_PIXELS; i++) {
        int p = (int)(((long)i * 7919 + 13) % (W * H)); /* scattered, every row band */
        x[i] = p % W;
        y[i] = p / W;
    }
    fm_render_params rp = fm_render_params_default();
    rp.width = W;
    rp.quality = FM_QUALITY_REFERENCE;
    rp.seed = REFERENCE_SEED + 1000;
    rp.reference_samples = SPOT_PATHS;
    float out[SPOT_PIXELS * 3], se[SPOT_PIXELS * 3];
    fm_error err;
    if (fm_render_pixels(sky, &rp, SPOT_PIXELS, x, y, out, se, &err))
        fail_msg("fm_render_pixels: %s", err.message);
    double z2 = 0.0, zs = 0.0, worst = 0.0;
    int n = 0;
    for (int i = 0; i < SPOT_PIXELS; i++) {
        int p = y[i] * W + x[i];
        double s = sqrt(map->se[p] * map->se[p] + (double)se[i * 3 + 1] * se[i * 3 + 1]);
        if (!(s > 0.0))
            continue;
        double z = (out[i * 3 + 1] - map->y[p]) / s;
        z2 += z * z;
        zs += z;
        worst = fmax(worst, fabs(z));
        n++;
    }
    assert_true(n > SPOT_PIXELS / 2);
    print_message("reference mode now vs stored: %d pixels, mean z^2 = %.3f, mean z = %+.3f, worst |z| = %.2f\n", n,
                  z2 / n, zs / n, worst);
    assert_true(z2 / n < 1.5);
    assert_true(fabs(zs / n) < 0.45);
    assert_true(worst < 5.0);
}

static void compare(const char *name, const char *description, double sun_elevation, double altitude_m,
                    const char *biome_name, double turbidity, int reference_paths, double worst_z)
{
    fm_sky_params p = test_params(sun_elevation, 0.0);
    p.observer_altitude_m = altitude_m;
    p.biome = biome_name;
    p.turbidity = turbidity;
    fm_sky *sky = test_sky(&p);
    static reference_map map;
    const char *regenerate = getenv("FM_REGENERATE");
    if (regenerate && strcmp(regenerate, "1") == 0) {
        fm_image *ref = test_render(sky, W, FM_QUALITY_REFERENCE, 0, REFERENCE_SEED, reference_paths, 1.0, 0);
        write_reference(name, description, reference_paths, ref, &map);
        fm_image_destroy(ref);
    } else {
        read_reference(name, &map);
        check_reference_still_holds(sky, &map);
    }
    fm_image *fast = test_render(sky, W, FM_QUALITY_FINAL, 0, 12, 0, 1.0, 0);
    double z2[3] = {0}, zs[3] = {0}, rel[3] = {0}, se2[3] = {0}, worst = 0.0;
    double seed_rel[FAST_SEEDS][3] = {{0}};
    long n[3] = {0};
    for (int s = 0; s < FAST_SEEDS; s++) {
        fm_image *f = s == 0 ? fast : test_render(sky, W, FM_QUALITY_FINAL, 0, 12 + s, 0, 1.0, 0);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                size_t i = ((size_t)y * W + x) * 3 + 1;
                if (map.se[y * W + x] > 0.0)
                    seed_rel[s][region_of(y)] += (f->pixels[i] - map.y[y * W + x]) / map.y[y * W + x];
            }
        if (f != fast)
            fm_image_destroy(f);
    }
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = ((size_t)y * W + x) * 3 + 1;
            double se = map.se[y * W + x], yr = map.y[y * W + x];
            if (!(se > 0.0))
                continue;
            double z = (fast->pixels[i] - yr) / se;
            int region = region_of(y);
            z2[region] += z * z;
            zs[region] += z;
            se2[region] += (se / yr) * (se / yr);
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
    fm_image_destroy(fast);
    fm_sky_destroy(sky);
}

static void noon(void **state) { compare("noon", "sun 30, no aerosols", 30.0, 0.0, "none", 1.0, 4096, 5.5); }
static void sunset(void **state) { compare("sunset", "sun 2, no aerosols", 2.0, 0.0, "none", 1.0, 4096, 5.5); }
static void eye_height(void **state)
{
    compare("eye-height", "sun 30, no aerosols, observer at 2 m", 30.0, 2.0, "none", 1.0, 2048, 5.5);
}
/* an aircraft at 10 km: the horizon dips 3.2 degrees and the ground is seen through the air below */
static void aircraft(void **state)
{
    compare("aircraft", "sun 30, no aerosols, observer at 10 km", 30.0, 10000.0, "none", 1.0, 1024, 5.5);
}
/* aerosols: the forward peak and absorption through both estimators */
static void rural_noon(void **state) { compare("rural-noon", "sun 30, rural", 30.0, 0.0, "rural", 1.0, 2048, 5.5); }
static void urban_sunset(void **state)
{
    compare("urban-sunset", "sun 2, urban, turbidity 2", 2.0, 0.0, "urban", 2.0, 2048, 5.5);
}
/* twilight: the sun 4 degrees down, the sky lit across the Earth's shadow (both estimators switch to
 * their twilight sampling, transport/twilight.h) */
static void twilight(void **state) { compare("twilight", "sun -4, rural", -4.0, 0.0, "rural", 1.0, 1024, 7.0); }

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

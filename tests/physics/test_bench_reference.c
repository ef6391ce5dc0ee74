/* The benchmark's converged references (tests/data/bench_reference/, written by bench/bench.sh
 * --make-reference: the reference mode at 400 probe pixels of each benchmark sky's 1024 x 512 map, 3e5
 * to 1.2e6 paths per pixel, hours of CPU) must stay what the reference mode renders today, or the
 * benchmark's "ref RMS" would measure a stale physics.  Each run renders PROBES of their pixels
 * afresh with PATHS paths and other random numbers and requires agreement within the joint noise:
 * z = (Y_now - Y_cached) / sqrt(se_now^2 + se_cached^2) per probe, mean z^2 < 1.6 and |mean z| <
 * 0.5 (4 standard deviations of that mean), every |z| < 5.  At the default sky each probe's noise
 * is about 0.6%, so a 1% change of the physics fails it; the sunset's about 3.5%. */
#include "bench_skies.h"
#include "check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define PROBES 64
#define PATHS 8192
#define SEED 77

static void check_sky(const char *name)
{
    const bench_sky *b = bench_sky_find(name);
    assert_non_null(b);
    char path[4096];
    snprintf(path, sizeof path, "%s/bench_reference/%s-1024.txt", FM_TEST_DATA_DIR, b->name);
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("cannot read %s (bench/bench.sh --make-reference writes it)", path);
    int W = 0, H = 0, n = 0;
    assert_true(bench_reference_header(f, &W, &H, &n));
    assert_true(W == 1024 && H == 512 && n >= PROBES);
    int x[PROBES], y[PROBES];
    double Y[PROBES], se[PROBES];
    for (int i = 0, kept = 0; i < n; i++) {
        int px, py;
        double v, s;
        assert_true(bench_reference_probe(f, W, H, &px, &py, &v, &s));
        if (i % (n / PROBES) || kept == PROBES)
            continue; /* every (n / PROBES)-th probe */
        x[kept] = px, y[kept] = py, Y[kept] = v, se[kept] = s;
        kept++;
    }
    fclose(f);

    fm_sky_params p = bench_sky_params(b);
    fm_sky *sky = test_sky(&p);
    fm_render_params rp = fm_render_params_default();
    rp.width = W;
    rp.quality = FM_QUALITY_REFERENCE;
    rp.reference_samples = PATHS;
    rp.seed = SEED;
    float out[3 * PROBES], out_se[3 * PROBES];
    fm_error err;
    if (fm_render_pixels(sky, &rp, PROBES, x, y, out, out_se, &err))
        fail_msg("fm_render_pixels: %s", err.message);
    double z2 = 0.0, zsum = 0.0, worst = 0.0, noise = 0.0;
    for (int i = 0; i < PROBES; i++) {
        double now = out[3 * i + 1], now_se = out_se[3 * i + 1];
        double z = (now - Y[i]) / sqrt(now_se * now_se + se[i] * se[i]);
        z2 += z * z;
        zsum += z;
        worst = fmax(worst, fabs(z));
        noise += now_se / now;
    }
    print_message("%s: %d probes now (%d paths, %.2f%% noise each) vs cached: mean z^2 = %.3f, mean z = %+.3f, "
                  "worst |z| = %.2f\n",
                  b->name, PROBES, PATHS, 100.0 * noise / PROBES, z2 / PROBES, zsum / PROBES, worst);
    assert_true(z2 / PROBES < 1.6);
    assert_true(fabs(zsum / PROBES) < 0.5);
    assert_true(worst < 5.0);
    fm_sky_destroy(sky);
}

static void default_sky(void **state) { check_sky("default"); }
static void sunset(void **state) { check_sky("sunset"); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(default_sky),
        cmocka_unit_test(sunset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

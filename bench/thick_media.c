/* thick-media-bench TAU G SSA ALBEDO PATHS [WIDTH]: the path tracer against adding-doubling for a
 * homogeneous cloud layer (tests/physics/thick_media_cases.h) at the precision test_thick_media has
 * no time for (issue 48).  Prints, each with the path tracer's standard error and its difference from
 * adding-doubling: the diffuse irradiance at the ground and the upward irradiance above the layer
 * (PATHS cosine-weighted paths each), the radiance at 7 directions from the ground (PATHS / 4 paths
 * each), and, if WIDTH > 0, a final-quality map's rows above 15 degrees (each row's mean over
 * azimuth) and its render time. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"
#include "thick_media_cases.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static void line(const char *what, double got, double se, double expected)
{
    printf("%-46s %.6g +- %.2f%%  adding-doubling %.6g  %+.2f%%\n", what, got, 100.0 * se / got, expected,
           100.0 * (got / expected - 1.0));
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: thick-media-bench TAU G SSA ALBEDO PATHS [WIDTH]\n");
        return 2;
    }
    cloud c = {atof(argv[1]), atof(argv[2]), atof(argv[3]), atof(argv[4])};
    int N = atoi(argv[5]), width = argc > 6 ? atoi(argv[6]) : 0;
    double mu0 = sin(CLOUD_SUN_ELEVATION * FM_DEG), se;
    static const double el[7] = {90, 60, 60, 35, 35, 15, 15}, az[7] = {0, 60, 180, 90, 180, 60, 180};
    double mu[7];
    for (int i = 0; i < 7; i++)
        mu[i] = sin(el[i] * FM_DEG);
    ad_solution s = cloud_reference(&c, 7, mu);
    printf("tau %g g %g ssa %g albedo %g, sun %g deg, %d paths\n", c.tau, c.g, c.ssa, c.albedo, CLOUD_SUN_ELEVATION, N);
    char *path;
    fm_sky *sky = cloud_sky(&c, 0.0, &path);
    double E = cloud_irradiance(sky, 1.0, N, 1, &se);
    line("diffuse irradiance at the ground", E, se, mu0 * s.flux_down_diffuse);
    path_context all = sky_path_context(sky, 1, 0);
    for (int i = 0; i < 7; i++) {
        double e = el[i] * FM_DEG, a = (180.0 + az[i]) * FM_DEG; /* the sun is due south */
        double L = test_path_radiance(&all, sky->observer, v3_normalize(v3(cos(e) * sin(a), cos(e) * cos(a), sin(e))),
                                      N / 4, 2, (uint64_t)i, &se);
        char what[64];
        snprintf(what, sizeof what, "radiance, elevation %2.0f azimuth %3.0f", el[i], az[i]);
        line(what, L, se, ad_radiance_bottom(&s, i, az[i] * FM_DEG));
    }
    if (width > 0) {
        int H = width / 2, rows = 0;
        double row_mu[64];
        while (rows < 64 && 90.0 - (rows + 0.5) * 180.0 / H > 15.0) {
            row_mu[rows] = sin((90.0 - (rows + 0.5) * 180.0 / H) * FM_DEG);
            rows++;
        }
        ad_solution m = cloud_reference(&c, rows, row_mu);
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        fm_image *img = test_render(sky, width, FM_QUALITY_FINAL, 0, 3, 0, 1.0, 0);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        double sum2 = 0.0;
        for (int y = 0; y < rows; y++) {
            double map = 0.0, ad = 0.0;
            for (int x = 0; x < width; x++) {
                map += test_pixel_y(img, x, y);
                ad += ad_radiance_bottom(&m, y, (((x + 0.5) / width - 0.25) * 360.0 - 180.0) * FM_DEG);
            }
            sum2 += (map / ad - 1.0) * (map / ad - 1.0);
            printf("final map %dx%d row elevation %4.1f: %+.2f%%\n", width, H, asin(row_mu[y]) / FM_DEG,
                   100.0 * (map / ad - 1.0));
        }
        printf("final map: rms row difference %.2f%%, render %.2f s wall\n", 100.0 * sqrt(sum2 / rows),
               (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
        fm_image_destroy(img);
        ad_free(&m);
    }
    drop_cloud_sky(sky, path);
    sky = cloud_sky(&c, 2500.0, &path);
    E = cloud_irradiance(sky, -1.0, N, 2, &se);
    line("upward irradiance above the layer", E, se, mu0 * s.flux_up_top);
    drop_cloud_sky(sky, path);
    ad_free(&s);
    return 0;
}

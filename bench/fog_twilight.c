/* fog-twilight-bench SUN_DEG PATHS [SEED [CLOUD]]: fog of 200 m visibility (or the cloud layer CLOUD,
 * presets/clouds/) around or above an observer on the ground in the built-in atmosphere, 550 nm, the sun SUN_DEG up (below FOG_TABLE_MIN_SUN_DEG: the column lit
 * by the sky above the fog, render/fog_incident.h), at the precision test_fog_twilight has no time
 * for (issue 48).  Prints the fast path's diffuse irradiance at the ground and radiances at 8 views
 * against the reference estimator's plain path tracing (PATHS cosine-weighted paths for the
 * irradiance, PATHS / 4 per view), each with its standard error. */
#include "check.h"

#include "base/rng.h"
#include "render/fog_table.h"
#include "render/ms_table.h"
#include "render/render.h"
#include "transport/path.h"
#include "transport/sky_path.h"
#include "transport/twilight.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static void line(const char *what, double fast, double ref, double se)
{
    printf("%-34s fast %.6g  reference %.6g +- %.2f%%  %+.2f%%\n", what, fast, ref, 100.0 * se / ref,
           100.0 * (fast / ref - 1.0));
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: fog-twilight-bench SUN_DEG PATHS [SEED [CLOUD]]\n");
        return 2;
    }
    const int N = atoi(argv[2]);
    const uint64_t seed = argc > 3 ? (uint64_t)atoll(argv[3]) : 1;
    fm_sky_params p = fm_sky_params_default();
    p.fog_visibility_m = argc > 4 ? 0.0 : 200.0;
    p.clouds = argc > 4 ? argv[4] : NULL;
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = atof(argv[1]);
    p.sun_azimuth_deg = 180.0;
    fm_sky *sky = test_sky(&p);
    fm_render_params rp = fm_render_params_default();
    rp.width = 64;
    ms_table ms = {0};
    render_job job = {.sky = sky, .params = &rp, .ms = &ms, .fine_fog_table = 1, .fog_from_above = 1};
    fm_error err;
    twilight_sampling *tw = NULL;
    if (render_start(&job, &err) || render_twilight(&job, &tw, &err))
        return 1;
    job.twilight = tw;
    if (render_fast_tables(&job, asin(sky->sun_dir.z), &err))
        return 1;
    printf("sun %s: the table from the %s\n", argv[1],
           fog_table_from_above(&job) ? "column lit by the sky above the fog" : job.paths_per_node ? "paths" : "column");
    path_context all = sky_path_context(sky, 1, 0);
    double diffuse, sum = 0.0, sum2 = 0.0;
    ground_irradiance_lookup(&job.ground, sky->sun_dir.z, &diffuse);
    for (int i = 0; i < N; i++) {
        rng r = rng_for(seed, 0, (uint64_t)i);
        double u1 = rng_uniform(&r), u2 = rng_uniform(&r), s = sqrt(u1), phi = 2.0 * FM_PI * u2;
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(&all, sky->observer, v3(s * cos(phi), s * sin(phi), sqrt(1.0 - u1)), 0, &r, L);
        sum += L[0];
        sum2 += L[0] * L[0];
    }
    const double mean = sum / N;
    line("diffuse irradiance at the ground", diffuse, FM_PI * mean, FM_PI * sqrt(fmax(0.0, sum2 / N - mean * mean) / N));
    static const double views[][2] = {{90, 0}, {60, 180}, {80, 0}, {30, 0}, {30, 90}, {30, 180}, {10, 0}, {10, 180},
                                       {3, 0}, {3, 90}, {3, 180}, {1, 0}, {1, 180}};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        const double e = views[i][0] * FM_DEG, phi = views[i][1] * FM_DEG;
        float v[1];
        sky_grid_lookup(&job.ss, e, phi, v);
        double L = v[0], se;
        sky_grid_lookup(&ms.grid, e, phi, v);
        L += v[0];
        const double ref = test_path_radiance(&all, sky->observer, render_view_direction(sky, e, phi), N / 4, seed,
                                              100 + i, &se);
        char what[64];
        snprintf(what, sizeof what, "radiance at elevation %.0f, azimuth %.0f", views[i][0], views[i][1]);
        line(what, L, ref, se);
    }
    free(tw);
    render_tables_free(&job);
    fm_image_destroy(job.img);
    fm_sky_destroy(sky);
    return 0;
}

/* The cloud optics cache's benchmark (aerosol/cloud_optics.h; docs/clouds.md "Optics"):
 *
 *   cloud-optics-bench [CLOUD]   for each water cloud type (or CLOUD), the CPU time of its optics on
 *                                the colour grid computed and read back from a cache file, and of a
 *                                whole sky build (fm_sky_create, CLOUD over the default sky) without a
 *                                cache and from a warm one.  One thread: CPU time, not wall time, is
 *                                what a loaded machine can measure. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, mkdtemp */

#include "firmament/firmament.h"

#include "aerosol/cloud_optics.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double table_s(const cloud_type *t, const spectral_grid *grid, const char *dir, cloud_optics_source *from)
{
    cloud_water_table tb;
    fm_error err;
    double t0 = cpu_now();
    if (cloud_water_table_get(t, grid, 1, dir, &tb, from, &err)) {
        fprintf(stderr, "cloud-optics-bench: %s\n", err.message);
        exit(1);
    }
    double s = cpu_now() - t0;
    cloud_water_table_free(&tb);
    return s;
}

static double sky_s(const char *cloud, const char *dir)
{
    fm_sky_params p = fm_sky_params_default();
    p.clouds = cloud;
    p.threads = 1;
    p.cache_dir = dir;
    fm_sky *sky;
    fm_error err;
    double t0 = cpu_now();
    if (fm_sky_create(&p, &sky, &err)) {
        fprintf(stderr, "cloud-optics-bench: %s\n", err.message);
        exit(1);
    }
    double s = cpu_now() - t0;
    fm_sky_destroy(sky);
    return s;
}

int main(int argc, char **argv)
{
    char dir[] = "/tmp/fm-cloud-optics-XXXXXX";
    if (!mkdtemp(dir))
        return 1;
    spectral_grid grid;
    spectral_grid_visible(&grid);
    printf("%-14s %12s %12s %14s %14s   (CPU s, one thread, %d wavelengths)\n", "type", "computed", "cached",
           "sky, no cache", "sky, cached", grid.count);
    for (const cloud_type *t = cloud_types; t->name; t++) {
        if (t->ice || (argc > 1 && strcmp(argv[1], t->name) != 0))
            continue;
        cloud_optics_source first, second;
        double computed = table_s(t, &grid, dir, &first), cached = table_s(t, &grid, dir, &second);
        double sky_cold = sky_s(t->name, NULL), sky_warm = sky_s(t->name, dir);
        const char *note = second != CLOUD_OPTICS_FROM_CACHE ? "   (cache not used!)"
                           : first == CLOUD_OPTICS_FROM_CACHE ? "   (an earlier type's droplets: its file)"
                                                              : "";
        printf("%-14s %12.3f %12.4f %14.3f %14.3f%s\n", t->name, computed, cached, sky_cold, sky_warm, note);
    }
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : 1;
}

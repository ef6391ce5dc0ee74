/* The speed benchmark's measurement of the reference mode (bench/bench.sh runs it): the reference
 * mode itself (fm_render_pixels: per-pixel path tracing, no tables) at PROBES pixels of the
 * benchmark sky's equirect map, its wall time per pixel and its RMS relative noise from its own
 * standard errors (it is unbiased: its error is its noise, falling as 1 / sqrt(paths)).
 *
 *   sky-bench args SKY                the firmament render options of the sky (default | sunset)
 *   sky-bench speed SKY WIDTH PATHS   prints "seconds_per_pixel T noise E paths N"
 *
 * Probe pixels: positions uniform over the map's pixels (the map's RMS weighs every pixel alike),
 * from a fixed hash, leaving out those within EXCLUDE_DEG of the sun (the benchmark's maps have no
 * disk; the aureole is kept). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include "firmament/firmament.h"

#include "base/rng.h"
#include "base/units.h"
#include "camera/equirect.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PROBES 400
#define EXCLUDE_DEG 1.0

typedef struct bench_sky {
    const char *name, *args;
    double sun_elevation, sun_azimuth, turbidity;
    const char *biome;
} bench_sky;

/* The skies of issue "Speed": the default sky and a sunset. */
static const bench_sky SKIES[] = {
    {"default", "--sun-elevation 30 --sun-azimuth 180 --biome rural --turbidity 1", 30.0, 180.0, 1.0, "rural"},
    {"sunset", "--sun-elevation 2 --sun-azimuth 180 --biome urban --turbidity 2", 2.0, 180.0, 2.0, "urban"},
};

static const bench_sky *find_sky(const char *name)
{
    for (size_t i = 0; i < sizeof SKIES / sizeof SKIES[0]; i++)
        if (strcmp(SKIES[i].name, name) == 0)
            return &SKIES[i];
    fprintf(stderr, "sky-bench: unknown sky '%s' (default | sunset)\n", name);
    exit(2);
}

static fm_sky *make_sky(const bench_sky *b)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = b->sun_elevation;
    p.sun_azimuth_deg = b->sun_azimuth;
    p.biome = b->biome;
    p.turbidity = b->turbidity;
    fm_sky *sky;
    fm_error err;
    if (fm_sky_create(&p, &sky, &err)) {
        fprintf(stderr, "sky-bench: %s\n", err.message);
        exit(1);
    }
    return sky;
}

static int probe_pixels(const bench_sky *b, int W, int *x, int *y)
{
    const int H = W / 2;
    vec3 sun = direction_from_elevation_azimuth(b->sun_elevation * FM_DEG, b->sun_azimuth * FM_DEG);
    int n = 0;
    for (uint64_t i = 0; n < PROBES; i++) {
        uint64_t h = mix64(i ^ 0x5EEDull);
        int px = (int)((h >> 32) % (uint64_t)W), py = (int)((h & 0xffffffffull) % (uint64_t)H);
        if (v3_dot(equirect_direction(W, H, px + 0.5, py + 0.5), sun) > cos(EXCLUDE_DEG * FM_DEG))
            continue;
        x[n] = px;
        y[n] = py;
        n++;
    }
    return n;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* Runs the reference mode at the probes; returns wall seconds.  Y and its standard error out. */
static double reference(const bench_sky *b, int W, int paths, uint64_t seed, const int *x, const int *y, int n,
                        double *Y, double *se)
{
    fm_sky *sky = make_sky(b);
    fm_render_params rp = fm_render_params_default();
    rp.width = W;
    rp.quality = FM_QUALITY_REFERENCE;
    rp.reference_samples = paths;
    rp.seed = seed;
    float *v = malloc(sizeof(float) * 3 * n), *s = malloc(sizeof(float) * 3 * n);
    fm_error err;
    double t0 = now();
    if (!v || !s || fm_render_pixels(sky, &rp, n, x, y, v, s, &err)) {
        fprintf(stderr, "sky-bench: %s\n", v && s ? err.message : "out of memory");
        exit(1);
    }
    double t = now() - t0;
    for (int i = 0; i < n; i++) {
        Y[i] = v[3 * i + 1];
        se[i] = s[3 * i + 1];
    }
    free(v);
    free(s);
    fm_sky_destroy(sky);
    return t;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "args") == 0) {
        printf("%s\n", find_sky(argv[2])->args);
        return 0;
    }
    if (argc == 5 && strcmp(argv[1], "speed") == 0) {
        const bench_sky *b = find_sky(argv[2]);
        int W = atoi(argv[3]), paths = atoi(argv[4]), x[PROBES], y[PROBES];
        if (W < 8 || W % 2 || paths < 2) {
            fprintf(stderr, "sky-bench: WIDTH must be even and at least 8, PATHS at least 2\n");
            return 2;
        }
        int n = probe_pixels(b, W, x, y);
        static double Y[PROBES], se[PROBES];
        double t = reference(b, W, paths, 1, x, y, n, Y, se), noise2 = 0.0;
        for (int i = 0; i < n; i++)
            noise2 += (se[i] / Y[i]) * (se[i] / Y[i]);
        printf("seconds_per_pixel %.6g noise %.6f paths %d\n", t / n, sqrt(noise2 / n), paths);
        return 0;
    }
    fprintf(stderr, "usage: sky-bench args SKY | speed SKY WIDTH PATHS\n");
    return 2;
}

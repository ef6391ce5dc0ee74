/* The speed benchmark's measurement of the reference mode (bench/bench.sh runs it): the reference
 * mode itself (fm_render_pixels: per-pixel path tracing, no tables) at PROBES pixels of the
 * benchmark sky's equirect map, its wall time per pixel and its RMS relative noise from its own
 * standard errors (it is unbiased: its error is its noise, falling as 1 / sqrt(paths)); and the
 * error of a fast map against a converged reference-mode estimate at those pixels, cached in
 * tests/data/bench_reference/ (a whole map that converged is out of reach: 10^5 to 10^7 paths per
 * pixel; a few hundred pixels are not, and their errors estimate the map's RMS error, noise and
 * bias together).
 *
 *   sky-bench args SKY                   the firmament render options of the sky (default | sunset |
 *                                        biome:NAME, sun 30 through that biome)
 *   sky-bench speed SKY WIDTH PATHS      prints "seconds_per_pixel T noise E paths N"
 *   sky-bench reference SKY WIDTH PATHS [SEED]
 *                                        prints the converged reference at the probes (the cache file;
 *                                        seed 1000003 unless given)
 *   sky-bench merge SKY WIDTH FILE...    prints the reference files' runs pooled into one (runs of other
 *                                        seeds add to a cached reference; each file weighted by the
 *                                        inverse square of its noise), and on stderr how each file
 *                                        agrees with the rest
 *   sky-bench error MAP.exr REFERENCE    prints "rms E noise N corrected C bias B probes P p99 Q": the
 *                                        map's relative luminance error at the reference's probes (a
 *                                        map k times as wide is averaged over k x k pixels first), the
 *                                        reference's own noise, the error with it taken out, and the
 *                                        99th percentile of |error| over the probes (noise left in)
 *   sky-bench seeds A.exr B.exr EV       prints one map's noise from two seeds' maps (seed_noise.h):
 *                                        "luminance L red_green R blue_green B grain G de_mean M
 *                                        de_p99 P" (relative, and CIEDE2000 as displayed at EV)
 *   sky-bench flicker A1.exr B1.exr A2.exr B2.exr
 *                                        prints "flicker F": one map's noise in the ratio of frames
 *                                        a and b (A1, B1 of one seed, A2, B2 of another)
 *
 * Probe pixels: positions uniform over the map's pixels (the map's RMS weighs every pixel alike),
 * from a fixed hash, leaving out those within EXCLUDE_DEG of the sun (the benchmark's maps have no
 * disk; the aureole is kept). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include "bench_skies.h"
#include "seed_noise.h"
#include "firmament/firmament.h"

#include "base/rng.h"
#include "base/units.h"
#include "camera/equirect.h"
#include "image/image.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PROBES 400
#define EXCLUDE_DEG 1.0

static const bench_sky *find_sky(const char *name)
{
    const bench_sky *b = bench_sky_find(name);
    if (!b) {
        fprintf(stderr, "sky-bench: unknown sky '%s' (default | sunset | biome:NAME)\n", name);
        exit(2);
    }
    return b;
}

static fm_sky *make_sky(const bench_sky *b)
{
    fm_sky_params p = bench_sky_params(b);
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

/* RMS relative noise of n estimates Y with standard errors se. */
static double rms_relative_noise(const double *Y, const double *se, int n)
{
    double noise2 = 0.0;
    for (int i = 0; i < n; i++)
        noise2 += (se[i] / Y[i]) * (se[i] / Y[i]);
    return sqrt(noise2 / n);
}

/* One run of the reference mode at the probes, or several pooled: its paths, seed and wall time. */
typedef struct reference_run {
    long long paths;
    unsigned long long seed;
    double wall_s;
} reference_run;

#define MAX_RUNS 64

/* The reference at the probes, as tests/data/bench_reference/SKY-WIDTH.txt: a header that ends with
 * one "# run:" line per run pooled in it, then per probe "x y Y se" (CIE Y in W m^-2 sr^-1 and its
 * standard error). */
static void print_reference(const bench_sky *b, int W, const reference_run *runs, int r, const int *x, const int *y,
                            int n, const double *Y, const double *se)
{
    long long paths = 0;
    for (int i = 0; i < r; i++)
        paths += runs[i].paths;
    printf("# The reference mode at %d probe pixels of the %d x %d map of the benchmark sky '%s' (%s,\n", n, W, W / 2,
           b->name, b->args);
    printf("# --no-sun-disk): %lld paths per pixel (the runs below, pooled), RMS relative noise %.4f%%.\n", paths,
           100.0 * rms_relative_noise(Y, se, n));
    printf("# Per probe: x y (pixel), CIE Y (W m^-2 sr^-1), its standard error.  Regenerate after a change of the\n");
    printf("# physics: bench/bench.sh --make-reference (hours); --extend-reference SKY PATHS adds a run.\n");
    for (int i = 0; i < r; i++)
        printf("# run: %lld paths, seed %llu, %.0f s wall\n", runs[i].paths, runs[i].seed, runs[i].wall_s);
    printf("%d %d %d\n", W, W / 2, n);
    for (int i = 0; i < n; i++)
        printf("%d %d %.9g %.9g\n", x[i], y[i], Y[i], se[i]);
}

static int write_reference(const bench_sky *b, int W, int paths, uint64_t seed)
{
    int x[PROBES], y[PROBES], n = probe_pixels(b, W, x, y);
    static double Y[PROBES], se[PROBES];
    reference_run run = {paths, (unsigned long long)seed, reference(b, W, paths, seed, x, y, n, Y, se)};
    print_reference(b, W, &run, 1, x, y, n, Y, se);
    return 0;
}

/* Reads a reference file of sky b: its runs (appended to runs[*r]) and probes, which must be b's
 * probes of a W-wide map.  0, or 1 with the problem said. */
static int read_reference(const char *path, const bench_sky *b, int W, reference_run *runs, int *r, double *Y,
                          double *se)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "sky-bench: cannot read %s\n", path);
        return 1;
    }
    char line[512], name[64];
    int before = *r, w = 0, h = 0, n = 0, x[PROBES], y[PROBES], bad = 0, named = 0;
    long pos = ftell(f);
    while (fgets(line, sizeof line, f) && line[0] == '#') {
        reference_run run;
        const char *sky = strstr(line, "benchmark sky '");
        if (sky && sscanf(sky, "benchmark sky '%63[^']'", name) == 1)
            named = strcmp(name, b->name) == 0;
        if (sscanf(line, "# run: %lld paths, seed %llu, %lf s wall", &run.paths, &run.seed, &run.wall_s) == 3) {
            if (*r == MAX_RUNS || run.paths < 2) {
                bad = 1;
                break;
            }
            runs[(*r)++] = run;
        }
        pos = ftell(f);
    }
    fseek(f, pos, SEEK_SET);
    int expected = probe_pixels(b, W, x, y);
    if (bad || !named || *r == before || !bench_reference_header(f, &w, &h, &n) || w != W || h != W / 2 ||
        n != expected) {
        fprintf(stderr, "sky-bench: %s: not a reference of sky '%s' at width %d with its '# run:' lines\n", path,
                b->name, W);
        fclose(f);
        return 1;
    }
    for (int i = 0; i < n; i++) {
        int px, py;
        if (!bench_reference_probe(f, w, h, &px, &py, &Y[i], &se[i]) || px != x[i] || py != y[i]) {
            fprintf(stderr, "sky-bench: %s: probe %d unreadable or not the sky's probe (%d, %d)\n", path, i + 1, x[i],
                    y[i]);
            fclose(f);
            return 1;
        }
    }
    fclose(f);
    return 0;
}

/* Pools the reference files of sky b (independent runs: their seeds must differ) into one, each
 * file weighted by the inverse square of its RMS relative noise over all probes, w_i (for runs of
 * one estimator, in proportion to their paths; a run of the reference mode after a change that
 * kept its expectation, e.g. a faster version, pools at its own efficiency): Y = sum w_i Y_i /
 * sum w_i, se^2 = sum w_i^2 se_i^2 / (sum w_i)^2.  One weight per file, not per probe: a probe's
 * standard error is correlated with its own estimate, and weighting by it would bias the mean.
 * Says on stderr how each file agrees with the others pooled (z per probe, as
 * test_bench_reference): runs of one physics give mean z^2 near 1 and mean z near 0 (its standard
 * deviation 1 / sqrt(probes)). */
static int merge_references(const bench_sky *b, int W, char **names, int files)
{
    static reference_run runs[MAX_RUNS];
    static double Y[MAX_RUNS][PROBES], se[MAX_RUNS][PROBES], total[PROBES], total_se[PROBES];
    int r = 0, x[PROBES], y[PROBES], n = probe_pixels(b, W, x, y);
    if (files > MAX_RUNS) {
        fprintf(stderr, "sky-bench: at most %d files\n", MAX_RUNS);
        return 2;
    }
    double weight[MAX_RUNS], all = 0.0;
    for (int f = 0; f < files; f++) {
        if (read_reference(names[f], b, W, runs, &r, Y[f], se[f]))
            return 1;
        double noise = rms_relative_noise(Y[f], se[f], n);
        weight[f] = 1.0 / (noise * noise);
        all += weight[f];
    }
    for (int i = 0; i < r; i++)
        for (int j = 0; j < i; j++)
            if (runs[i].seed == runs[j].seed) {
                fprintf(stderr, "sky-bench: two runs with seed %llu: the same random numbers, not independent\n",
                        runs[i].seed);
                return 1;
            }
    for (int i = 0; i < n; i++) {
        double sum = 0.0, var = 0.0;
        for (int f = 0; f < files; f++) {
            sum += weight[f] * Y[f][i];
            var += weight[f] * weight[f] * se[f][i] * se[f][i];
        }
        total[i] = sum / all;
        total_se[i] = sqrt(var) / all;
    }
    for (int f = 0; f < files && files > 1; f++) {
        double z2 = 0.0, zsum = 0.0, rest = all - weight[f];
        for (int i = 0; i < n; i++) {
            /* the other files pooled: their sums less this file's */
            double others = (all * total[i] - weight[f] * Y[f][i]) / rest;
            double others_var = (all * all * total_se[i] * total_se[i] - weight[f] * weight[f] * se[f][i] * se[f][i]) /
                                (rest * rest);
            double z = (Y[f][i] - others) / sqrt(se[f][i] * se[f][i] + fmax(others_var, 0.0));
            z2 += z * z;
            zsum += z;
        }
        fprintf(stderr, "sky-bench: %s against the others: mean z^2 %.3f, mean z %+.3f (+-%.3f)\n", names[f], z2 / n,
                zsum / n, 1.0 / sqrt(n));
    }
    print_reference(b, W, runs, r, x, y, n, total, total_se);
    return 0;
}

/* CIE Y of pixel (x, y) of a colour map (XYZ, Rec.709 or another RGB space), as firmament compare. */
static double map_luminance(const fm_image *m, int x, int y)
{
    const float *p = &m->pixels[((size_t)y * m->width + x) * m->channels];
    double v[3] = {p[0], p[1], p[2]}, xyz[3];
    image_colour_to_xyz(m, v, xyz);
    return xyz[1];
}

static int ascending(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The map's relative luminance error at the n probes that follow in the reference file f (of a W x H
 * map); 0, or 1 with the problem said. */
static int probe_errors(const fm_image *m, FILE *f, const char *ref_path, int W, int H, int n)
{
    if (n > PROBES) {
        fprintf(stderr, "sky-bench: %s holds %d probes, more than the %d of a benchmark reference\n", ref_path, n,
                PROBES);
        return 1;
    }
    const int k = m->width / W;
    double e2 = 0.0, noise2 = 0.0, bias = 0.0;
    static double abs_e[PROBES];
    for (int i = 0; i < n; i++) {
        int x, y;
        double Y, se;
        if (!bench_reference_probe(f, W, H, &x, &y, &Y, &se)) {
            fprintf(stderr, "sky-bench: %s: probe %d unreadable\n", ref_path, i + 1);
            return 1;
        }
        double sum = 0.0; /* the k x k pixels of the larger map that make up probe pixel (x, y) */
        for (int dy = 0; dy < k; dy++)
            for (int dx = 0; dx < k; dx++)
                sum += map_luminance(m, k * x + dx, k * y + dy);
        double e = sum / (k * k) / Y - 1.0;
        e2 += e * e;
        bias += e;
        noise2 += (se / Y) * (se / Y);
        abs_e[i] = fabs(e);
    }
    double rms = sqrt(e2 / n), noise = sqrt(noise2 / n);
    /* the 99th percentile taken as `firmament compare` takes it over a map's pixels (fm_image_compare) */
    qsort(abs_e, (size_t)n, sizeof abs_e[0], ascending);
    int p99 = (int)fmin(n - 1.0, floor(0.99 * n));
    printf("rms %.6f noise %.6f corrected %.6f bias %.6f probes %d p99 %.6f\n", rms, noise,
           sqrt(fmax(0.0, rms * rms - noise * noise)), bias / n, n, abs_e[p99]);
    return 0;
}

static int map_error(const char *map_path, const char *ref_path)
{
    fm_image *m;
    fm_error err;
    if (fm_image_read_exr(map_path, &m, &err)) {
        fprintf(stderr, "sky-bench: %s\n", err.message);
        return 1;
    }
    FILE *f = fopen(ref_path, "r");
    int status = 1;
    if (!f) {
        fprintf(stderr, "sky-bench: cannot read %s\n", ref_path);
    } else {
        int W = 0, H = 0, n = 0;
        if (!bench_reference_header(f, &W, &H, &n) || m->width % W ||
            m->height * W != H * m->width || m->channels != 3 ||
            (m->content != FM_IMAGE_XYZ && m->content != FM_IMAGE_RGB_REC709 && m->content != FM_IMAGE_RGB))
            fprintf(stderr, "sky-bench: %s does not match %s (a colour map, a multiple of %d x %d)\n", map_path,
                    ref_path, W, H);
        else
            status = probe_errors(m, f, ref_path, W, H, n);
        fclose(f);
    }
    fm_image_destroy(m);
    return status;
}

/* Reads n EXR maps; 0, or 1 with the problem said (none left allocated). */
static int read_maps(char **paths, int n, fm_image **maps)
{
    for (int i = 0; i < n; i++) {
        fm_error err;
        if (fm_image_read_exr(paths[i], &maps[i], &err)) {
            fprintf(stderr, "sky-bench: %s\n", err.message);
            while (i-- > 0)
                fm_image_destroy(maps[i]);
            return 1;
        }
    }
    return 0;
}

static int seeds(char **paths, const char *ev_text)
{
    char *end = NULL;
    double ev = strtod(ev_text, &end);
    fm_image *m[2];
    if (end == ev_text || *end || !isfinite(ev) || fabs(ev) > 100.0) {
        fprintf(stderr, "sky-bench: EV must be a number in [-100, 100], not '%s'\n", ev_text);
        return 2;
    }
    if (read_maps(paths, 2, m))
        return 1;
    seed_noise s;
    int status = seed_noise_measure(m[0], m[1], ev, &s);
    if (!status)
        printf("luminance %.6f red_green %.6f blue_green %.6f grain %.6f de_mean %.4f de_p99 %.4f\n", s.luminance,
               s.red_green, s.blue_green, s.grain, s.de_mean, s.de_p99);
    fm_image_destroy(m[0]);
    fm_image_destroy(m[1]);
    return status;
}

static int flicker(char **paths)
{
    fm_image *m[4];
    if (read_maps(paths, 4, m))
        return 1;
    double f;
    int status = seed_flicker(m[0], m[1], m[2], m[3], &f);
    if (!status)
        printf("flicker %.6f\n", f);
    for (int i = 0; i < 4; i++)
        fm_image_destroy(m[i]);
    return status;
}

int main(int argc, char **argv)
{
    const char *command = argc >= 2 ? argv[1] : "";
    if (argc == 3 && strcmp(command, "args") == 0) {
        printf("%s\n", find_sky(argv[2])->args);
        return 0;
    }
    int is_reference = strcmp(command, "reference") == 0;
    if ((argc == 5 && strcmp(command, "speed") == 0) || (is_reference && (argc == 5 || argc == 6))) {
        const bench_sky *b = find_sky(argv[2]);
        int W = atoi(argv[3]), paths = atoi(argv[4]), x[PROBES], y[PROBES];
        if (W < 8 || W % 2 || paths < 2) {
            fprintf(stderr, "sky-bench: WIDTH must be even and at least 8, PATHS at least 2\n");
            return 2;
        }
        char *end = NULL;
        unsigned long long seed = argc == 6 ? strtoull(argv[5], &end, 10) : 1000003;
        if (argc == 6 && (end == argv[5] || *end)) {
            fprintf(stderr, "sky-bench: SEED must be a whole number, not '%s'\n", argv[5]);
            return 2;
        }
        if (is_reference)
            return write_reference(b, W, paths, seed);
        int n = probe_pixels(b, W, x, y);
        static double Y[PROBES], se[PROBES];
        double t = reference(b, W, paths, 1, x, y, n, Y, se);
        printf("seconds_per_pixel %.6g noise %.6f paths %d\n", t / n, rms_relative_noise(Y, se, n), paths);
        return 0;
    }
    if (argc == 4 && strcmp(command, "error") == 0)
        return map_error(argv[2], argv[3]);
    if (argc == 5 && strcmp(command, "seeds") == 0)
        return seeds(argv + 2, argv[4]);
    if (argc == 6 && strcmp(command, "flicker") == 0)
        return flicker(argv + 2);
    if (argc >= 5 && strcmp(command, "merge") == 0) {
        int W = atoi(argv[3]);
        if (W < 8 || W % 2) {
            fprintf(stderr, "sky-bench: WIDTH must be even and at least 8\n");
            return 2;
        }
        return merge_references(find_sky(argv[2]), W, argv + 4, argc - 4);
    }
    fprintf(stderr, "usage: sky-bench args SKY | speed SKY WIDTH PATHS | reference SKY WIDTH PATHS [SEED] | error "
                    "MAP.exr REFERENCE | merge SKY WIDTH FILE... | seeds A.exr B.exr EV | flicker A1.exr B1.exr A2.exr "
                    "B2.exr\n");
    return 2;
}

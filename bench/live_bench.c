/* The live sky's benchmark (bench/bench.sh --live runs it; docs/rendering.md "Live sky").
 * BIOME is a biome's name (none, rural, urban, ...; the default sky otherwise), with "+fogV" after it
 * for fog of visibility V metres on the ground (--fog-visibility V): rural+fog200.
 *
 *   live-bench speed BIOME [SUNS]       builds the live sky of BIOME on every core, prints its build
 *                                       time (the whole; then its parts: fm_sky_live_create, what a
 *                                       first map by day waits for, and the twilight band that a
 *                                       first sun below 1 degree adds) and table memory, then
 *                                       renders SUNS (default 40) suns
 *                                       spread over -20..90 degrees and every azimuth to 512 x 256
 *                                       maps written as EXR + sidecar (/tmp), twice: in half floats without the sun
 *                                       disk (the add-on's live maps), then in floats with it; prints
 *                                       the median and 90th percentile of the time per map, its
 *                                       render and write parts, their CPU times, and the process's
 *                                       peak memory
 *   live-bench accuracy BIOME WIDTH E... the live map at each sun elevation E against the final quality
 *                                       path at the same sun (sun disk left out, aureole kept; the
 *                                       azimuth 180): luminance RMS of the relative error, its mean
 *                                       (bias) and 99th percentile, and the mean and largest u'v'
 *                                       chromaticity distance; with "ref N" after WIDTH, the reference is
 *                                       the mean of N final maps (seeds 0..N-1), and its own noise (the
 *                                       seeds' spread: the RMS of each pixel's standard error over its
 *                                       luminance) and the RMS less it (in quadrature) are printed too;
 *                                       with "noise" after those, also the RMS of a further final seed
 *                                       against the reference; with "seeds N" (after those), N builds
 *                                       whose nodes' seeds are moved (the live sky's `seed`): the means
 *                                       over them (the largest u'v') and each build's RMS and bias; final maps
 *                                       are kept in $LIVE_BENCH_FINAL_CACHE when set (a directory)
 *   live-bench bands BIOME              builds the live sky of BIOME band by band (deep twilight with its
 *                                       shared flight columns, the twilight above it, the day: nodes at
 *                                       0 degrees and up, whose shared walks stay within the band) and
 *                                       prints each band's nodes, wall and CPU time: where the build's
 *                                       time goes
 *   live-bench refine BIOME WIDTH ref N ROUNDS [seed S] E...
 *                                       the product's build (with "seed S", the build whose nodes' seeds
 *                                       are moved by S, as accuracy's seeds) refined round by round
 *                                       (fm_sky_live_refine)
 *                                       up to ROUNDS: each round's CPU time, and after each (0: as
 *                                       built) the live map at each E against the mean of N final seeds
 *                                       as accuracy's ref N (RMS, bias, the reference's noise, the RMS
 *                                       less it)
 *   live-bench sweep BIOME FROM TO STEP the zenith luminance (cd/m^2) of the live map from FROM to TO
 *                                       degrees in steps of STEP, and the largest step of its logarithm
 *                                       across a grid elevation against the largest elsewhere */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include "firmament/firmament.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/platform.h"
#include "image/image.h"
#include "render/live.h"
#include "transport/twilight.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The process's CPU time (s): on a machine shared with other jobs, what the wall time would be on
 * one idle core. */
static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* BIOME[+fogV]: the biome and the fog's visibility (m); the name is cut at the '+' in place. */
static fm_sky_params params_for(const char *biome_arg)
{
    static char name[64];
    fm_sky_params p = fm_sky_params_default();
    snprintf(name, sizeof name, "%s", biome_arg);
    char *fog = strstr(name, "+fog");
    if (fog) {
        *fog = '\0';
        p.fog_visibility_m = atof(fog + 4);
    }
    p.biome = name;
    return p;
}

static double build_cpu_s; /* of the last build */

static fm_sky_live *build(const char *biome_arg, double *seconds)
{
    fm_sky_params p = params_for(biome_arg);
    fm_sky_live *live;
    fm_error err;
    double t0 = now(), c0 = cpu_now();
    if (fm_sky_live_create(&p, NULL, &live, &err)) {
        fprintf(stderr, "live-bench: %s\n", err.message);
        exit(1);
    }
    *seconds = now() - t0;
    build_cpu_s = cpu_now() - c0;
    return live;
}

static size_t table_bytes(const fm_sky_live *live)
{
    size_t n = 0;
    for (int i = 0; i < live->count; i++)
        n += sizeof(float) * (size_t)live->channels *
             (size_t)(sky_grid_nodes(&live->nodes[i].ss) + sky_grid_nodes(&live->nodes[i].ms)) +
             sizeof(float) * aureole_floats(&live->nodes[i].aureole);
    return n;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double percentile(double *v, int n, double q)
{
    qsort(v, (size_t)n, sizeof *v, by_value);
    return v[(int)fmin(n - 1, floor(q * n))];
}

/* Maps of SUNS suns spread over -20..90 degrees and every azimuth, written as `half` (half floats,
 * ZIP, no sun disk: the add-on's live maps) or as the default (32-bit floats, ZIP, the disk): the
 * median and 90th percentile of the wall time per map, its render and write parts, and the median
 * CPU time of each part. */
static int maps(fm_sky_live *live, const char *biome_arg, int suns, int half)
{
    double *v = malloc(sizeof(double) * suns * 6), *total = v, *render = v + suns, *write = v + 2 * suns,
           *cpu = v + 3 * suns, *cpu_render = v + 4 * suns, *cpu_write = v + 5 * suns;
    for (int i = 0; i < suns; i++) {
        double e = -20.0 + 110.0 * (i + 0.5) / suns, a = fmod(137.5 * i, 360.0);
        fm_render_params rp = fm_render_params_default();
        rp.width = 512;
        rp.sun_disk = !half;
        fm_image *img;
        fm_output *out;
        fm_error err;
        double t0 = now(), c0 = cpu_now();
        if (fm_sky_live_render(live, e, a, &rp, &img, &err) ||
            (render[i] = now() - t0, cpu_render[i] = cpu_now() - c0, fm_image_to_rec709(img, &err)) ||
            fm_output_open("/tmp/live_bench.exr", "/tmp/live_bench.json", &out, &err) ||
            fm_output_set_format(out, half, FM_EXR_ZIP, &err) || fm_output_commit(out, img, NULL, &err)) {
            fprintf(stderr, "live-bench: %s\n", err.message);
            return 1;
        }
        fm_output_close(out);
        fm_image_destroy(img);
        total[i] = now() - t0;
        write[i] = total[i] - render[i];
        cpu[i] = cpu_now() - c0;
        cpu_write[i] = cpu[i] - cpu_render[i];
    }
    printf("%-8s 512 x 256 map per sun (%d suns, %s): median %5.1f ms (render %5.1f, write %5.1f), p90 %5.1f ms; "
           "CPU median %5.1f ms (render %5.1f, write %5.1f)\n",
           biome_arg, suns, half ? "half, no disk" : "float, disk", 1e3 * percentile(total, suns, 0.5),
           1e3 * percentile(render, suns, 0.5), 1e3 * percentile(write, suns, 0.5), 1e3 * percentile(total, suns, 0.9),
           1e3 * percentile(cpu, suns, 0.5), 1e3 * percentile(cpu_render, suns, 0.5),
           1e3 * percentile(cpu_write, suns, 0.5));
    free(v);
    return 0;
}

static int speed(const char *biome_arg, int suns)
{
    double first_s;
    double m0 = platform_peak_memory_mib();
    fm_sky_live *live = build(biome_arg, &first_s);
    const double first_cpu_s = build_cpu_s, t0 = now(), c0 = cpu_now();
    fm_error err;
    if (fm_sky_live_complete(live, NULL, &err)) {
        fprintf(stderr, "live-bench: %s\n", err.message);
        return 1;
    }
    const double deep_s = now() - t0, deep_cpu_s = cpu_now() - c0;
    printf("%-8s build %6.2f s wall, %6.2f s CPU  nodes %d  tables %6.2f MiB  peak after build %6.1f MiB (before "
           "%5.1f)\n",
           biome_arg, first_s + deep_s, first_cpu_s + deep_cpu_s, live->count, table_bytes(live) / 1048576.0,
           platform_peak_memory_mib(), m0);
    printf("%-8s build to the first map %6.2f s wall, %6.2f s CPU; twilight band (a first sun below 1) "
           "%6.2f s wall, %6.2f s CPU\n",
           biome_arg, first_s, first_cpu_s, deep_s, deep_cpu_s);
    int s = maps(live, biome_arg, suns, 1) || maps(live, biome_arg, suns, 0);
    printf("%-8s peak %6.1f MiB\n", biome_arg, platform_peak_memory_mib());
    fm_sky_live_destroy(live);
    return s;
}

/* The band of a node's sun elevation: 0 deep twilight, 1 the twilight above it, 2 the day. */
static int band_of(double e) { return e >= 0.0 ? 2 : (twilight_deep(e) ? 0 : 1); }

static int bands(const char *biome_arg)
{
    static const char *const name[] = {"deep twilight", "twilight", "day"};
    fm_sky_params p = params_for(biome_arg);
    double wall = 0.0, cpu = 0.0;
    for (int b = 0; b < 3; b++) {
        fm_sky_live *live;
        fm_error err;
        if (live_alloc(&p, &live, &err)) {
            fprintf(stderr, "live-bench: %s\n", err.message);
            return 1;
        }
        double lo = INFINITY, hi = -INFINITY;
        int nodes = 0;
        for (int i = 0; i < live->count; i++)
            if (band_of(live->nodes[i].sun_elevation_deg) == b) {
                lo = fmin(lo, live->nodes[i].sun_elevation_deg);
                hi = fmax(hi, live->nodes[i].sun_elevation_deg);
                nodes++;
            }
        double t0 = now(), c0 = cpu_now();
        if (nodes && live_build_nodes(live, lo, hi, NULL, &err)) {
            fprintf(stderr, "live-bench: %s\n", err.message);
            return 1;
        }
        double w = now() - t0, c = cpu_now() - c0;
        wall += w;
        cpu += c;
        printf("%-8s %-13s %2d nodes %6.1f..%5.1f  %6.2f s wall, %6.2f s CPU\n", biome_arg, name[b], nodes, lo, hi, w, c);
        fm_sky_live_destroy(live);
    }
    printf("%-8s all bands               %6.2f s wall, %6.2f s CPU\n", biome_arg, wall, cpu);
    return 0;
}

static fm_image *final_render(const char *biome_arg, double e, int width, uint64_t seed)
{
    fm_sky_params p = params_for(biome_arg);
    p.sun_elevation_deg = e;
    fm_sky *sky;
    fm_image *img;
    fm_error err;
    fm_render_params rp = fm_render_params_default();
    rp.width = width;
    rp.sun_disk = 0;
    rp.seed = seed;
    if (fm_sky_create(&p, &sky, &err) || fm_render(sky, &rp, &img, &err)) {
        fprintf(stderr, "live-bench: %s\n", err.message);
        exit(1);
    }
    fm_sky_destroy(sky);
    return img;
}

/* The final path's map, kept in $LIVE_BENCH_FINAL_CACHE (a directory) when set: a deep twilight map
 * costs minutes of CPU, and the live sky's experiments compare against the same ones (whoever changes
 * the final path empties the directory). */
static fm_image *final_map(const char *biome_arg, double e, int width, uint64_t seed)
{
    const char *dir = getenv("LIVE_BENCH_FINAL_CACHE");
    char path[4096];
    snprintf(path, sizeof path, "%s/final-%s-%g-%d-%llu.f32", dir ? dir : ".", biome_arg, e, width,
             (unsigned long long)seed);
    FILE *f = dir ? fopen(path, "rb") : NULL;
    if (f) {
        fm_image *img = image_create(width, width / 2, 3, FM_IMAGE_XYZ, 0, 0);
        const size_t n = (size_t)img->width * img->height * 3;
        size_t got = fread(img->pixels, sizeof(float), n, f);
        fclose(f);
        if (got == n)
            return img;
        fm_image_destroy(img);
    }
    fm_image *img = final_render(biome_arg, e, width, seed);
    if (dir && (f = fopen(path, "wb"))) {
        fwrite(img->pixels, sizeof(float), (size_t)img->width * img->height * 3, f);
        fclose(f);
    }
    return img;
}

/* The reference: the mean of `n` final maps (seeds 0..n-1); *noise_rms the root mean square over the
 * pixels of its estimated standard error over its luminance (the seeds' spread over sqrt(n)), 0 for
 * one map. */
static fm_image *final_reference(const char *biome_arg, double e, int width, int n, double *noise_rms)
{
    fm_image *ref = final_map(biome_arg, e, width, 0);
    const size_t px = (size_t)ref->width * ref->height;
    double *sum = calloc(px, sizeof(double)), *sum2 = calloc(px, sizeof(double));
    for (int s = 0; s < n; s++) {
        fm_image *img = s ? final_map(biome_arg, e, width, (uint64_t)s) : ref;
        for (size_t i = 0; i < px; i++) {
            sum[i] += img->pixels[3 * i + 1];
            sum2[i] += (double)img->pixels[3 * i + 1] * img->pixels[3 * i + 1];
            if (s)
                for (int c = 0; c < 3; c++)
                    ref->pixels[3 * i + c] += img->pixels[3 * i + c];
        }
        if (s)
            fm_image_destroy(img);
    }
    double var = 0.0;
    long used = 0;
    for (size_t i = 0; i < px; i++) {
        for (int c = 0; c < 3; c++)
            ref->pixels[3 * i + c] /= (float)n;
        const double m = sum[i] / n;
        if (n > 1 && m > 0.0) {
            var += fmax(0.0, sum2[i] / n - m * m) / (n - 1) / (m * m);
            used++;
        }
    }
    *noise_rms = used ? sqrt(var / used) : 0.0;
    free(sum);
    free(sum2);
    return ref;
}

/* A map's RMS against a reference of several seeds less that reference's own noise (noise_rms, as
 * final_reference gives it), in quadrature: the error of the map itself. */
static double rms_less_noise(double rms, double noise_rms)
{
    return sqrt(fmax(0.0, rms * rms - noise_rms * noise_rms));
}

/* u'v' (CIE 1976) of an XYZ pixel. */
static void uv(const float *xyz, double *u, double *v)
{
    double d = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
    *u = d > 0.0 ? 4.0 * xyz[0] / d : 0.0;
    *v = d > 0.0 ? 9.0 * xyz[1] / d : 0.0;
}

/* Mean and largest u'v' distance over the pixels brighter than 1e-6 of b's mean luminance. */
static void chromaticity(const fm_image *a, const fm_image *b, double *mean, double *max)
{
    const size_t n = (size_t)a->width * a->height;
    double ymean = 0.0;
    for (size_t i = 0; i < n; i++)
        ymean += b->pixels[3 * i + 1] / (double)n;
    double sum = 0.0;
    long used = 0;
    *max = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (!(b->pixels[3 * i + 1] > 1e-6 * ymean))
            continue;
        double ua, va, ub, vb;
        uv(&a->pixels[3 * i], &ua, &va);
        uv(&b->pixels[3 * i], &ub, &vb);
        double d = hypot(ua - ub, va - vb);
        sum += d;
        used++;
        *max = fmax(*max, d);
    }
    *mean = used ? sum / used : 0.0;
}

/* The live sky of BIOME with its nodes' seeds moved by `seed` (0: the product's). */
static fm_sky_live *build_seeded(const char *biome_arg, uint64_t seed)
{
    if (!seed) {
        double build_s;
        return build(biome_arg, &build_s);
    }
    fm_sky_params p = params_for(biome_arg);
    fm_sky_live *live;
    fm_error err;
    if (live_alloc(&p, &live, &err) || (live->seed = seed, live_build_nodes(live, -90.0, 90.0, NULL, &err))) {
        fprintf(stderr, "live-bench: %s\n", err.message);
        exit(1);
    }
    return live;
}

static int accuracy(const char *biome_arg, int width, int noise, int refs, int seeds, int count, char **elevations)
{
    fm_sky_live **live = malloc(sizeof *live * (size_t)seeds);
    for (int s = 0; s < seeds; s++)
        live[s] = build_seeded(biome_arg, (uint64_t)s);
    printf("%-8s %7s %8s %8s %8s %9s %9s%s%s%s\n", "biome", "sun", "RMS %", "bias %", "p99 %", "u'v' mean", "u'v' max",
           refs > 1 ? "  ref noise %  RMS less it %" : "", noise ? "  final noise RMS %" : "",
           seeds > 1 ? "  RMS % of each build" : "");
    for (int i = 0; i < count; i++) {
        double e = atof(elevations[i]);
        fm_render_params rp = fm_render_params_default();
        rp.width = width;
        rp.sun_disk = 0;
        double ref_noise;
        fm_image *want = final_reference(biome_arg, e, width, refs, &ref_noise);
        fm_error err;
        double rms[64], bias[64], sum[4] = {0}, uv_max = 0.0;
        for (int s = 0; s < seeds; s++) {
            fm_image *got;
            if (fm_sky_live_render(live[s], e, 180.0, &rp, &got, &err)) {
                fprintf(stderr, "live-bench: %s\n", err.message);
                return 1;
            }
            fm_comparison c;
            fm_image_compare(got, want, 0.0, &c, &err);
            double uv_mean, uv_largest;
            chromaticity(got, want, &uv_mean, &uv_largest);
            rms[s] = c.rms;
            bias[s] = c.mean;
            sum[0] += c.rms / seeds;
            sum[1] += c.mean / seeds;
            sum[2] += c.p99 / seeds;
            sum[3] += uv_mean / seeds;
            uv_max = fmax(uv_max, uv_largest);
            fm_image_destroy(got);
        }
        printf("%-8s %7.2f %8.3f %8.3f %8.3f %9.5f %9.5f", biome_arg, e, 100 * sum[0], 100 * sum[1], 100 * sum[2], sum[3],
               uv_max);
        if (refs > 1)
            printf("  %11.3f  %12.3f", 100 * ref_noise, 100 * rms_less_noise(sum[0], ref_noise));
        if (noise) {
            fm_image *other = final_map(biome_arg, e, width, (uint64_t)refs);
            fm_comparison n;
            fm_image_compare(other, want, 0.0, &n, &err);
            printf("  %8.3f", 100 * n.rms);
            fm_image_destroy(other);
        }
        for (int s = 0; s < seeds && seeds > 1; s++)
            printf(" %6.2f", 100 * rms[s]);
        for (int s = 0; s < seeds && seeds > 1; s++)
            printf(" %s%+.2f", s ? "" : " bias ", 100 * bias[s]);
        printf("\n");
        fflush(stdout);
        fm_image_destroy(want);
    }
    for (int s = 0; s < seeds; s++)
        fm_sky_live_destroy(live[s]);
    free(live);
    return 0;
}

/* The live sky of BIOME (its nodes' seeds moved by `seed`; 0: the product's) refined round by round
 * (fm_sky_live_refine) up to `rounds`: per
 * round its CPU time, then at each sun the live map against the mean of `refs` final seeds (as
 * accuracy's ref N): RMS, bias, the reference's noise and the RMS less it. */
static int refine(const char *biome_arg, int width, int refs, int rounds, uint64_t seed, int count, char **elevations)
{
    fm_sky_live *live = build_seeded(biome_arg, seed);
    fm_error err;
    if (fm_sky_live_complete(live, NULL, &err)) {
        fprintf(stderr, "live-bench: %s\n", err.message);
        return 1;
    }
    fm_image **want = malloc(sizeof *want * (size_t)count);
    double *ref_noise = malloc(sizeof *ref_noise * (size_t)count);
    for (int i = 0; i < count; i++)
        want[i] = final_reference(biome_arg, atof(elevations[i]), width, refs, &ref_noise[i]);
    printf("%-8s %7s %6s %9s %8s %8s %12s %13s\n", "biome", "sun", "round", "CPU s", "RMS %", "bias %", "ref noise %",
           "RMS less it %");
    for (int r = 0; r <= rounds; r++) {
        const double cpu0 = cpu_now();
        if (r > 0 && fm_sky_live_refine(live, NULL, &err)) {
            fprintf(stderr, "live-bench: %s\n", err.message);
            return 1;
        }
        const double cpu = cpu_now() - cpu0;
        if (fm_sky_live_rounds(live) != r) {
            fprintf(stderr, "live-bench: the library refines %d rounds at most\n", fm_sky_live_rounds(live));
            break;
        }
        for (int i = 0; i < count; i++) {
            fm_render_params rp = fm_render_params_default();
            rp.width = width;
            rp.sun_disk = 0;
            fm_image *got;
            fm_comparison c;
            if (fm_sky_live_render(live, atof(elevations[i]), 180.0, &rp, &got, &err) ||
                fm_image_compare(got, want[i], 0.0, &c, &err)) {
                fprintf(stderr, "live-bench: %s\n", err.message);
                return 1;
            }
            printf("%-8s %7.2f %6d %9.2f %8.3f %8.3f %12.3f %13.3f\n", biome_arg, atof(elevations[i]), r, cpu,
                   100 * c.rms, 100 * c.mean, 100 * ref_noise[i],
                   100 * rms_less_noise(c.rms, ref_noise[i]));
            fflush(stdout);
            fm_image_destroy(got);
        }
    }
    for (int i = 0; i < count; i++)
        fm_image_destroy(want[i]);
    free(want);
    free(ref_noise);
    fm_sky_live_destroy(live);
    return 0;
}

/* Mean luminance (cd/m^2) of the map's top row: the zenith. */
static double zenith(fm_sky_live *live, double e)
{
    fm_render_params rp = fm_render_params_default();
    rp.width = 64;
    rp.sun_disk = 0;
    rp.threads = 1;
    fm_image *img;
    fm_error err;
    if (fm_sky_live_render(live, e, 180.0, &rp, &img, &err)) {
        fprintf(stderr, "live-bench: %s\n", err.message);
        exit(1);
    }
    double y = 0.0;
    for (int x = 0; x < img->width; x++)
        y += img->pixels[3 * x + 1] * 683.0 / img->width;
    fm_image_destroy(img);
    return y;
}

static int sweep(const char *biome_arg, double from, double to, double step)
{
    double build_s;
    fm_sky_live *live = build(biome_arg, &build_s);
    /* suns half a step off the grid's elevations, so that each of them lies inside one step */
    const int n = (int)floor((to - from) / step);
    double prev = zenith(live, from + 0.5 * step), across = 0.0, elsewhere = 0.0, worst_at = from;
    for (int k = 1; k < n; k++) {
        double e = from + (k + 0.5) * step, y = zenith(live, e), d = fabs(log(y / prev));
        int crosses = 0;
        for (int i = 0; i < live->count; i++)
            crosses |= live->nodes[i].sun_elevation_deg > e - step && live->nodes[i].sun_elevation_deg < e;
        printf("%7.2f %12.6g %s\n", e, y, crosses ? "grid" : "");
        if (crosses && d > across)
            across = d, worst_at = e;
        if (!crosses)
            elsewhere = fmax(elsewhere, d);
        prev = y;
    }
    printf("%-8s zenith luminance steps of %.2f deg: largest across a grid elevation %.4f (at %.2f), elsewhere "
           "%.4f (log)\n",
           biome_arg, step, across, worst_at, elsewhere);
    fm_sky_live_destroy(live);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && !strcmp(argv[1], "speed"))
        return speed(argv[2], argc > 3 ? atoi(argv[3]) : 40);
    if (argc >= 5 && !strcmp(argv[1], "accuracy")) {
        int at = 4, refs = 1, seeds = 1;
        if (at + 1 < argc && !strcmp(argv[at], "ref")) {
            refs = atoi(argv[at + 1]);
            at += 2;
        }
        const int noise = at < argc && !strcmp(argv[at], "noise");
        at += noise;
        if (at + 1 < argc && !strcmp(argv[at], "seeds")) {
            seeds = atoi(argv[at + 1]);
            at += 2;
        }
        if (refs >= 1 && refs <= 64 && seeds >= 1 && seeds <= 64 && at < argc)
            return accuracy(argv[2], atoi(argv[3]), noise, refs, seeds, argc - at, argv + at);
    }
    if (argc >= 8 && !strcmp(argv[1], "refine") && !strcmp(argv[4], "ref") && atoi(argv[5]) >= 1 &&
        atoi(argv[5]) <= 64 && atoi(argv[6]) >= 0) {
        const int seeded = argc >= 10 && !strcmp(argv[7], "seed");
        return refine(argv[2], atoi(argv[3]), atoi(argv[5]), atoi(argv[6]),
                      seeded ? strtoull(argv[8], NULL, 10) : 0, argc - 7 - 2 * seeded, argv + 7 + 2 * seeded);
    }
    if (argc == 3 && !strcmp(argv[1], "bands"))
        return bands(argv[2]);
    if (argc == 6 && !strcmp(argv[1], "sweep"))
        return sweep(argv[2], atof(argv[3]), atof(argv[4]), atof(argv[5]));
    fprintf(stderr, "usage: live-bench speed BIOME [SUNS] | accuracy BIOME WIDTH [ref N] [noise] [seeds N] E... | refine BIOME WIDTH ref N ROUNDS [seed S] E... | sweep BIOME FROM "
                    "TO "
                    "STEP\n");
    return 2;
}

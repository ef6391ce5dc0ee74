#include "transport/ground_irradiance.h"

#include "base/rng.h"
#include "base/threads.h"
#include "base/units.h"

#include <math.h>
#include <stdlib.h>

#define ITEM_GROUND 0x300000000ull

typedef struct build_job {
    ground_irradiance *g;
    const path_context *pc;
    int paths, nodes;
    uint64_t seed;
} build_job;

/* Work item = (node, block of paths); blocks are summed per node afterwards in a fixed order. */
#define BLOCK 1024

static void build_blocks(void *ctx, int64_t begin, int64_t end, int thread)
{
    build_job *job = ctx;
    ground_irradiance *g = job->g;
    const int K = g->K;
    int blocks = (job->paths + BLOCK - 1) / BLOCK;
    const atmosphere *atm = job->pc->atm;
    for (int64_t item = begin; item < end; item++) {
        int node = (int)(item / blocks), block = (int)(item % blocks);
        double theta = g->theta0 + node * g->dtheta;
        /* a ground point whose zenith makes the angle theta with the sun: rotate the sun direction */
        vec3 s = job->pc->sun_dir;
        frame f = frame_from_normal(s);
        vec3 up = v3_normalize(frame_to_world(&f, v3(sin(theta), 0.0, cos(theta))));
        vec3 origin = v3_scale(up, atm->bottom_radius_m);
        frame local = frame_from_normal(up);
        double *out = &g->E[((size_t)node * blocks + block) * K];
        int first = block * BLOCK, last = first + BLOCK < job->paths ? first + BLOCK : job->paths;
        int offset = (int)(mix64(job->seed ^ (uint64_t)node) % (uint64_t)K);
        for (int p = first; p < last; p++) {
            rng r = rng_for_qmc(job->seed, ITEM_GROUND + (uint64_t)node, (uint64_t)p, (uint64_t)job->paths);
            double u1 = rng_uniform(&r), u2 = rng_uniform(&r), sr = sqrt(u1), phi = 2.0 * FM_PI * u2;
            vec3 d = v3_normalize(frame_to_world(&local, v3(sr * cos(phi), sr * sin(phi), sqrt(1.0 - u1))));
            path_trace(job->pc, origin, d, (p + offset) % K, &r, out);
        }
    }
}

fm_status ground_irradiance_build(ground_irradiance *g, const path_context *all_orders, double theta_s,
                                  double max_offset, int paths, uint64_t seed, int threads, const atomic_int *cancel)
{
    const int K = all_orders->atm->grid.count;
    double lo = fmax(0.0, theta_s - max_offset), hi = fmin(FM_PI, theta_s + max_offset);
    g->K = K;
    g->count = hi - lo < 1e-4 ? 1 : 5;
    g->theta0 = g->count == 1 ? theta_s : lo;
    g->dtheta = g->count == 1 ? 0.0 : (hi - lo) / (g->count - 1);
    int blocks = (paths + BLOCK - 1) / BLOCK;
    /* per-block sums first (any thread may run any block), then a fixed-order reduction */
    double *partial = calloc((size_t)g->count * blocks * K, sizeof(double));
    g->E = calloc((size_t)g->count * K, sizeof(double));
    if (!partial || !g->E) {
        free(partial);
        ground_irradiance_free(g);
        return FM_ERR_OUT_OF_MEMORY;
    }
    ground_irradiance staging = *g;
    staging.E = partial;
    build_job job = {&staging, all_orders, paths, g->count, seed};
    fm_status s = parallel_for(threads, (int64_t)g->count * blocks, 1, build_blocks, &job, cancel, NULL);
    for (int n = 0; n < g->count; n++)
        for (int b = 0; b < blocks; b++)
            for (int k = 0; k < K; k++)
                g->E[(size_t)n * K + k] += partial[((size_t)n * blocks + b) * K + k];
    for (size_t i = 0; i < (size_t)g->count * K; i++)
        g->E[i] *= FM_PI / paths;
    free(partial);
    return s;
}

void ground_irradiance_free(ground_irradiance *g)
{
    free(g->E);
    g->E = NULL;
    g->count = 0;
}

void ground_irradiance_lookup(const ground_irradiance *g, double mu_s, double *E)
{
    const int K = g->K;
    double f = g->count == 1 ? 0.0 : (acos(fmin(1.0, fmax(-1.0, mu_s))) - g->theta0) / g->dtheta;
    f = fmin(fmax(f, 0.0), g->count - 1.0);
    int i = (int)f;
    if (i > g->count - 2)
        i = g->count > 1 ? g->count - 2 : 0;
    double t = g->count == 1 ? 0.0 : f - i;
    const double *a = &g->E[(size_t)i * K], *b = g->count == 1 ? a : a + K;
    for (int k = 0; k < K; k++)
        E[k] = a[k] * (1.0 - t) + b[k] * t;
}

#include "transport/ground_irradiance_build.h"

#include "base/quadrature.h"
#include "base/rng.h"
#include "base/threads.h"
#include "base/units.h"
#include "spectrum/spectral.h"
#include "transport/path.h"
#include "transport/single_scatter.h"
#include "transport/sun_frame.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>

#define ITEM_GROUND 0x300000000ull

typedef struct build_job {
    ground_irradiance *g;
    const path_context *pc;
    int paths, nodes;
    uint64_t seed;
    ground_quadrature quadrature;
    atomic_int no_memory;
} build_job;

/* The local sun zenith angle of node's ground point. */
static double node_theta(const ground_irradiance *g, int node) { return g->theta0 + node * g->dtheta; }

/* The zenith of node's ground point: the sun direction rotated by that angle. */
static vec3 ground_up(const build_job *job, int node)
{
    double theta = node_theta(job->g, node);
    frame f = frame_from_normal(job->pc->sun_dir);
    return v3_normalize(frame_to_world(&f, v3(sin(theta), 0.0, cos(theta))));
}

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
        vec3 up = ground_up(job, node);
        vec3 origin = v3_scale(up, atm->bottom_radius_m);
        frame local = frame_from_normal(up);
        double *out = &g->E[((size_t)node * blocks + block) * K];
        int first = block * BLOCK, last = first + BLOCK < job->paths ? first + BLOCK : job->paths;
        int offset = (int)(mix64(job->seed ^ (uint64_t)node) % (uint64_t)K);
        for (int p = first; p < last; p++) {
            rng r = rng_for_qmc(job->seed, ITEM_GROUND + (uint64_t)node, (uint64_t)p, (uint64_t)job->paths);
            double u1 = rng_uniform(&r), u2 = rng_uniform(&r);
            vec3 d = frame_cosine_direction(&local, u1, u2);
            path_trace(job->pc, origin, d, (p + offset) % K, &r, out);
        }
    }
}

/* Order 1 by quadrature on the ground point's sky, in elevation e and azimuth phi from the sun:
 *     E1 = integral L1 sin e cos e de dphi  over e in [0, pi/2], phi in [0, 2 pi),
 * symmetric about the sun's vertical plane (phi in [0, pi], counted twice).  Gauss-Legendre in
 * variables that crowd the nodes where radiance changes fastest: the elevations [0, e_c] and
 * [e_c, pi/2] apart (e_c the sun's elevation clamped to the hemisphere), the first crowded at both
 * ends (the horizon's bright rim, the sun), the second at e_c; the azimuth crowded at the sun's
 * (accuracy: docs/decisions/2026-12-06-quadrature-accuracy.md).  Each row shares its view ray's
 * part (single_scatter.h).  Work item = (node, row); rows are summed afterwards in a fixed order. */
#define FAR_FROM_SUN (12.0 * FM_DEG) /* rows this far from the sun's elevation: a quarter of the columns */

/* Row r's elevation and weight (d elevation) for a sun at elevation e_s. */
static void single_row(int r, int rows, double e_s, double *e, double *de)
{
    double e_c = fmin(fmax(e_s, 0.0), 0.5 * FM_PI);
    int lo = (int)lround(rows * e_c / (0.5 * FM_PI));
    if (r < lo) {
        const gauss_rule *g = gauss_legendre_cached(lo);
        double v = 0.5 * (g->x[r] + 1.0);
        *e = 0.5 * e_c * (1.0 - cos(FM_PI * v));
        *de = 0.5 * e_c * FM_PI * sin(FM_PI * v) * 0.5 * g->w[r];
    } else {
        const gauss_rule *g = gauss_legendre_cached(rows - lo);
        double v = 0.5 * (g->x[r - lo] + 1.0), span = 0.5 * FM_PI - e_c;
        *e = e_c + span * v * v;
        *de = 2.0 * span * v * 0.5 * g->w[r - lo];
    }
}

static void single_rows(void *ctx, int64_t begin, int64_t end, int thread)
{
    build_job *job = ctx;
    ground_irradiance *g = job->g;
    const int K = g->K;
    const atmosphere *atm = job->pc->atm;
    for (int64_t item = begin; item < end; item++) {
        const int rows = job->quadrature.rows;
        int node = (int)(item / rows), row = (int)(item % rows);
        double theta = node_theta(g, node);
        vec3 origin = v3_scale(ground_up(job, node), atm->bottom_radius_m);
        sun_frame f = sun_frame_at(origin, job->pc->sun_dir);
        double e, de;
        single_row(row, rows, 0.5 * FM_PI - theta, &e, &de);
        single_scatter_ray ray;
        if (single_scatter_ray_init(&ray, job->pc, origin, sun_frame_direction(&f, sin(e), 0.0),
                                    job->quadrature.points)) {
            atomic_store(&job->no_memory, 1);
            return;
        }
        double *out = &g->E[((size_t)node * rows + row) * K];
        /* away from the sun's elevation radiance is smooth in azimuth */
        const int full = job->quadrature.cols;
        const int cols = fabs(e - (0.5 * FM_PI - theta)) < FAR_FROM_SUN ? full : (full + 3) / 4;
        const gauss_rule *gc = gauss_legendre_cached(cols);
        for (int c = 0; c < cols; c++) {
            double w = 0.5 * (gc->x[c] + 1.0);
            double phi = FM_PI * w * w, dphi = 2.0 * FM_PI * w * 0.5 * gc->w[c];
            double L[FM_MAX_WAVELENGTHS] = {0};
            single_scatter_ray_radiance(&ray, job->pc, sun_frame_direction(&f, sin(e), phi), L);
            double weight = 2.0 * sin(e) * cos(e) * de * dphi;
            spectral_add_scaled(out, weight, L, K);
        }
        single_scatter_ray_free(&ray);
    }
}

fm_status ground_irradiance_build(ground_irradiance *g, const path_context *all_orders, double theta_s,
                                  double max_offset, ground_quadrature quadrature, int paths, uint64_t seed,
                                  int threads, const atomic_int *cancel)
{
    const int K = all_orders->atm->grid.count;
    double lo = fmax(0.0, theta_s - max_offset), hi = fmin(FM_PI, theta_s + max_offset);
    g->K = K;
    g->count = ground_irradiance_angle_count(theta_s, max_offset);
    g->theta0 = g->count == 1 ? theta_s : lo;
    g->dtheta = g->count == 1 ? 0.0 : (hi - lo) / (g->count - 1);
    int blocks = (paths + BLOCK - 1) / BLOCK;
    /* per-block sums first (any thread may run any block), then a fixed-order reduction */
    double *partial = calloc((size_t)g->count * blocks * K + 1, sizeof(double)); /* + 1: paths may be 0 */
    g->E = calloc((size_t)g->count * K, sizeof(double));
    if (!partial || !g->E) {
        free(partial);
        ground_irradiance_free(g);
        return FM_ERR_OUT_OF_MEMORY;
    }
    const int rows = quadrature.rows;
    double *single = calloc((size_t)g->count * rows * K, sizeof(double));
    if (!single) {
        free(partial);
        ground_irradiance_free(g);
        return FM_ERR_OUT_OF_MEMORY;
    }
    /* order 1 by quadrature, orders >= 2 by paths */
    const int with_first = all_orders->min_order <= 1;
    path_context higher = *all_orders;
    higher.min_order = with_first ? 2 : all_orders->min_order;
    path_context first = *all_orders;
    first.ground_diffuse = NULL; /* upward rays never meet the ground */
    ground_irradiance staging = *g;
    staging.E = single;
    build_job job = {&staging, &first, paths, g->count, seed, quadrature, 0};
    fm_status s = with_first ? parallel_for(threads, (int64_t)g->count * rows, 1, single_rows, &job, cancel, NULL) : FM_OK;
    staging.E = partial;
    job.pc = &higher;
    if (!s && atomic_load(&job.no_memory))
        s = FM_ERR_OUT_OF_MEMORY;
    if (!s && blocks > 0)
        s = parallel_for(threads, (int64_t)g->count * blocks, 1, build_blocks, &job, cancel, NULL);
    for (int n = 0; n < g->count; n++) {
        for (int b = 0; b < blocks; b++)
            for (int k = 0; k < K; k++)
                g->E[(size_t)n * K + k] += partial[((size_t)n * blocks + b) * K + k] * (FM_PI / paths);
        for (int row = 0; row < rows; row++)
            spectral_add(&g->E[(size_t)n * K], &single[((size_t)n * rows + row) * K], K);
    }
    free(partial);
    free(single);
    return s;
}

#include "render/reference.h"

#include "base/rng.h"
#include "camera/equirect.h"

#include <assert.h>
#include <math.h>

/* One equirect pixel of the reference: N paths through uniformly jittered positions in it; the mean
 * and its standard error per channel. */
void reference_pixel(const render_job *job, const path_context *pc, int x, int y, int N, float *mean_out,
                            float *se_out)
{
    const fm_sky *sky = job->sky;
    const int W = job->cam.width, H = job->cam.height, C = job->channels, K = sky->atm.grid.count;
    uint64_t item = ITEM_PIXEL + (uint64_t)y * W + x;
    int offset = (int)(mix64(job->seed ^ item) % (uint64_t)K);
    double sum[FM_MAX_WAVELENGTHS] = {0}, sum2[FM_MAX_WAVELENGTHS] = {0};
    for (int p = 0; p < N; p++) {
        rng r = rng_for(job->seed, item, (uint64_t)p);
        double jx = rng_uniform(&r), jy = rng_uniform(&r);
        vec3 d = equirect_direction(W, H, x + jx, y + jy);
        assert(fabs(v3_length(d) - 1.0) < 1e-12);
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(pc, sky->observer, d, (p + offset) % K, &r, L);
        float v[FM_MAX_WAVELENGTHS];
        render_channels(&sky->atm, C, L, v);
        for (int c = 0; c < C; c++) {
            sum[c] += v[c];
            sum2[c] += (double)v[c] * v[c];
        }
    }
    for (int c = 0; c < C; c++) {
        double mean = sum[c] / N;
        double var = N > 1 ? fmax(0.0, (sum2[c] - N * mean * mean) / (N - 1)) : 0.0;
        mean_out[c] = (float)mean;
        se_out[c] = (float)sqrt(var / N);
    }
}

void reference_rows(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    fm_image *img = job->img;
    const int W = img->width, C = job->channels;
    path_context pc = twilight_path_context(job->sky, job->twilight, 1, 0);
    for (int64_t y = begin; y < end; y++)
        for (int x = 0; x < W; x++) {
            size_t i = ((size_t)y * W + x) * C;
            reference_pixel(job, &pc, x, (int)y, job->q.reference_paths, &img->pixels[i], &img->std_error[i]);
        }
}

/* Reference through the fisheye and pinhole cameras: paths through uniformly jittered positions in
 * the pixel, weighted by the camera's solid angle per pixel area (the pixel's value is the
 * solid-angle mean of radiance over its footprint, as in the fast path); positions outside the
 * fisheye's circle carry no weight.  Standard error of the weighted mean from the weighted spread. */
void reference_rows_camera(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    const fm_sky *sky = job->sky;
    fm_image *img = job->img;
    const int W = img->width, C = job->channels, K = sky->atm.grid.count;
    const int N = job->q.reference_paths;
    path_context pc = twilight_path_context(job->sky, job->twilight, 1, 0);
    for (int64_t y = begin; y < end; y++) {
        for (int x = 0; x < W; x++) {
            uint64_t item = ITEM_PIXEL + (uint64_t)y * W + x;
            int offset = (int)(mix64(job->seed ^ item) % (uint64_t)K);
            /* sums of w v, and of w^2, w^2 v, w^2 v^2 for the spread */
            double wsum = 0.0, w2sum = 0.0, sum[FM_MAX_WAVELENGTHS] = {0}, w2v[FM_MAX_WAVELENGTHS] = {0};
            double w2v2[FM_MAX_WAVELENGTHS] = {0};
            int used = 0;
            for (int p = 0; p < N; p++) {
                rng r = rng_for(job->seed, item, (uint64_t)p);
                double jx = rng_uniform(&r), jy = rng_uniform(&r);
                vec3 d;
                double w = camera_sample(&job->cam, x + jx, y + jy, &d);
                if (!(w > 0.0))
                    continue; /* outside the fisheye's circle */
                assert(fabs(v3_length(d) - 1.0) < 1e-12);
                double L[FM_MAX_WAVELENGTHS] = {0};
                path_trace(&pc, sky->observer, d, (p + offset) % K, &r, L);
                float v[FM_MAX_WAVELENGTHS];
                render_channels(&sky->atm, C, L, v);
                for (int c = 0; c < C; c++) {
                    sum[c] += w * v[c];
                    w2v[c] += w * w * v[c];
                    w2v2[c] += w * w * (double)v[c] * v[c];
                }
                wsum += w;
                w2sum += w * w;
                used++;
            }
            size_t i = ((size_t)y * W + x) * C;
            for (int c = 0; c < C; c++) {
                double mean = wsum > 0.0 ? sum[c] / wsum : 0.0;
                /* sum w^2 (v - mean)^2 / (sum w)^2, with the n / (n - 1) of the unweighted case */
                double spread = w2v2[c] - 2.0 * mean * w2v[c] + mean * mean * w2sum;
                double var = used > 1 ? fmax(0.0, spread) / (wsum * wsum) * used / (used - 1) : 0.0;
                img->pixels[i + c] = (float)mean;
                img->std_error[i + c] = (float)sqrt(var);
            }
        }
    }
}

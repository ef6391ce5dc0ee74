/* The reference quality: every pixel path-traces all orders itself, no table of radiance; the
 * mean over its paths and the standard error of that mean. */
#ifndef FM_RENDER_REFERENCE_H
#define FM_RENDER_REFERENCE_H

#include "render/render_job.h"

/* One equirect pixel: N paths through uniformly jittered positions in it; the mean and its
 * standard error per channel. */
void reference_pixel(const render_job *job, const path_context *pc, int x, int y, int N, float *mean_out,
                     float *se_out);

/* Work items (threads.h): rows of the equirect map, and rows through the fisheye and pinhole cameras. */
void reference_rows(void *ctx, int64_t begin, int64_t end, int thread);
void reference_rows_camera(void *ctx, int64_t begin, int64_t end, int thread);

#endif

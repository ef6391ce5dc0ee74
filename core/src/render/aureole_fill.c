#include "render/aureole_fill.h"

#include "base/threads.h"
#include "render/channels.h"
#include "render/fog_table.h"
#include "transport/single_scatter.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdatomic.h>

#define NODE_ABOVE_HORIZON (0.1 * FM_DEG)

typedef struct fill_job {
    const render_job *job;
    aureole *a;
    aureole_frame f;
    double horizon;
    atomic_int no_memory;
} fill_job;

/* Work item: one row of the grid; nodes below the horizon take the sky's just above it (their
 * weight is 0; their cells' upper corners stay sky). */
static void fill_rows(void *ctx, int64_t begin, int64_t end, int thread)
{
    fill_job *fj = ctx;
    const render_job *job = fj->job;
    const fm_sky *sky = job->sky;
    path_context pc = sky_path_context(sky, 1, 1);
    pc.ground_diffuse = &job->ground;
    (void)thread;
    for (int64_t row = begin; row < end; row++)
        for (int col = 0; col < AUREOLE_COLS; col++) {
            double gamma, psi, e, phi, L[FM_MAX_WAVELENGTHS] = {0};
            aureole_node((int)row, col, &gamma, &psi);
            aureole_direction(&fj->f, gamma, psi, &e, &phi);
            e = fmax(e, fj->horizon + NODE_ABOVE_HORIZON);
            vec3 d = render_view_direction(sky, e, phi);
            single_scatter_ray ray;
            if (single_scatter_ray_init(&ray, &pc, sky->observer, d, job->q.ss_points)) {
                atomic_store(&fj->no_memory, 1);
                return;
            }
            single_scatter_ray_radiance(&ray, &pc, d, L);
            single_scatter_ray_free(&ray);
            float v[FM_MAX_WAVELENGTHS], peak[FM_MAX_WAVELENGTHS] = {0};
            render_channels(&sky->atm, fj->a->channels, L, v);
            if (job->ms) /* in fog, what the single-scattering table holds besides (fog_table_add_peak) */
                fog_table_peak(job, d, peak);
            float *out = &fj->a->values[((size_t)row * AUREOLE_COLS + col) * fj->a->channels];
            for (int c = 0; c < fj->a->channels; c++)
                out[c] = logf(fmaxf(v[c] + peak[c], FM_GRID_FLOOR));
        }
}

fm_status aureole_fill(aureole *a, const render_job *job, double sun_elevation)
{
    fill_job fj = {.job = job, .a = a, .f = aureole_frame_of(sun_elevation), .horizon = job->ss.horizon_elevation};
    atomic_init(&fj.no_memory, 0);
    fm_status s = parallel_for(job->params->threads, AUREOLE_ROWS, 1, fill_rows, &fj, job->params->cancel, NULL);
    return s ? s : (atomic_load(&fj.no_memory) ? FM_ERR_OUT_OF_MEMORY : FM_OK);
}

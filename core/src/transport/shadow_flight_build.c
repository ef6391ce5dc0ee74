#include "transport/shadow_flight_build.h"

#include "base/threads.h"
#include "base/units.h"
#include "spectrum/spectral_grid.h"
#include "transport/single_scatter.h"
#include "transport/sun_frame.h"

#include <math.h>
#include <stdatomic.h>

/* The sphere average of I: rows of elevation crowded at the point's horizon (where the sunlit air
 * is seen at twilight), columns of azimuth from the sun over one half (the sky is symmetric about the
 * sun's vertical), 2 quadrature points per ray piece: a density needs no accurate integral
 * (docs/decisions/2026-12-06-sampling-densities.md). */
#define ROWS_DOWN 6
#define ROWS_UP 10
#define HALF_COLS 8
#define QUADRATURE_POINTS 2

static double row_elevation(int j, double eh) { return sun_frame_row_elevation(j, eh, ROWS_DOWN, ROWS_UP); }

typedef struct build_job {
    shadow_flight_table *t;
    const path_context *single;
    sun_frame observer;
    double top;
    atomic_int no_memory;
} build_job;

/* Work item: one (altitude, local sun elevation) point. */
static void build_points(void *ctx, int64_t begin, int64_t end, int thread)
{
    build_job *job = ctx;
    const atmosphere *atm = job->single->atm;
    shadow_flight_table *t = job->t;
    for (int64_t item = begin; item < end; item++) {
        int i = (int)(item / SHADOW_FLIGHT_SUNS), j = (int)(item % SHADOW_FLIGHT_SUNS);
        double beta = j * t->sun_step; /* the angle travelled toward the sun from the observer */
        double radius = fmin(t->bottom_radius + shadow_flight_level_km[i] * FM_KM, job->top);
        vec3 position = sun_frame_toward_sun(&job->observer, beta, radius);
        sun_frame f = sun_frame_at(position, job->single->sun_dir);
        double eh = -acos(fmin(1.0, t->bottom_radius / radius)), sum = 0.0;
        for (int row = 0; row < ROWS_DOWN + ROWS_UP; row++) {
            double e0 = row_elevation(row, eh), e1 = row_elevation(row + 1, eh), e = 0.5 * (e0 + e1);
            double omega = (sin(e1) - sin(e0)) * FM_PI / HALF_COLS;
            single_scatter_ray ray;
            if (single_scatter_ray_init(&ray, job->single, position, sun_frame_direction(&f, sin(e), 0.0),
                                        QUADRATURE_POINTS)) {
                atomic_store(&job->no_memory, 1);
                return;
            }
            for (int c = 0; c < HALF_COLS; c++) {
                double L[FM_MAX_WAVELENGTHS] = {0};
                vec3 d = sun_frame_direction(&f, sin(e), FM_PI * (c + 0.5) / HALF_COLS);
                single_scatter_ray_radiance(&ray, job->single, d, L);
                sum += 2.0 * fmax(spectral_grid_luminance(&atm->grid, L), 0.0) * omega;
            }
            single_scatter_ray_free(&ray);
        }
        t->value[i][j] = sum / (4.0 * FM_PI);
    }
}

#define AMBIENT_POINTS 48

/* t->ambient from t->value (shadow_flight_table): one level per work item. */
static void build_ambient(void *ctx, int64_t begin, int64_t end, int thread)
{
    build_job *job = ctx;
    shadow_flight_table *t = job->t;
    for (int64_t i = begin; i < end; i++) {
        double radius = fmin(t->bottom_radius + shadow_flight_level_km[i] * FM_KM, job->top);
        vec3 position = sun_frame_toward_sun(&job->observer, 0.0, radius);
        sun_frame f = sun_frame_at(position, job->single->sun_dir);
        double eh = -acos(fmin(1.0, t->bottom_radius / radius)), sum = 0.0;
        for (int row = 0; row < ROWS_DOWN + ROWS_UP; row++) {
            double e0 = row_elevation(row, eh), e1 = row_elevation(row + 1, eh), e = 0.5 * (e0 + e1);
            double omega = (sin(e1) - sin(e0)) * FM_PI / HALF_COLS;
            for (int c = 0; c < HALF_COLS; c++) {
                ray_segment seg;
                ray_segment_init(&seg, job->single->atm, position,
                                 sun_frame_direction(&f, sin(e), FM_PI * (c + 0.5) / HALF_COLS));
                sum += 2.0 * shadow_flight_light_along(t, job->single, &seg, AMBIENT_POINTS) * omega;
            }
        }
        t->ambient[i] = sum / (4.0 * FM_PI);
    }
}

fm_status shadow_flight_build(shadow_flight_table *t, const path_context *single, vec3 observer, int threads,
                              const atomic_int *cancel)
{
    const atmosphere *atm = single->atm;
    build_job job = {.t = t, .single = single, .top = atm->top_radius_m - 1.0};
    job.observer = sun_frame_at(observer, single->sun_dir);
    t->bottom_radius = atm->bottom_radius_m;
    t->sun0 = asin(clamp_cosine(v3_dot(job.observer.up, single->sun_dir)));
    t->sun_step = 1.0 * FM_DEG;
    for (int k = 0, i = 0; k <= SHADOW_FLIGHT_TOP_KM; k++) {
        while (i < SHADOW_FLIGHT_LEVELS - 2 && k > shadow_flight_level_km[i + 1])
            i++;
        t->level_at_km[k] = (unsigned char)i;
    }
    atomic_init(&job.no_memory, 0);
    fm_status s = parallel_for(threads, (int64_t)SHADOW_FLIGHT_LEVELS * SHADOW_FLIGHT_SUNS, 1, build_points, &job,
                               cancel, NULL);
    if (!s && atomic_load(&job.no_memory))
        s = FM_ERR_OUT_OF_MEMORY;
    return s ? s : parallel_for(threads, SHADOW_FLIGHT_LEVELS, 1, build_ambient, &job, cancel, NULL);
}


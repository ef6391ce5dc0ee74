#include "transport/shadow_flight_build.h"

#include "base/threads.h"
#include "base/units.h"
#include "spectrum/spectral_grid.h"
#include "transport/single_scatter.h"
#include "transport/sun_frame.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>

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
    double *value;     /* [level][suns]: I of the points, column j beta = j * step toward the sun */
    int suns;
    double step;       /* rad */
    atomic_int no_memory;
} build_job;

/* Work item: one (altitude, local sun elevation) point. */
static void build_points(void *ctx, int64_t begin, int64_t end, int thread)
{
    build_job *job = ctx;
    const atmosphere *atm = job->single->atm;
    for (int64_t item = begin; item < end; item++) {
        int i = (int)(item / job->suns), j = (int)(item % job->suns);
        double beta = j * job->step; /* the angle travelled toward the sun from the observer */
        double radius = fmin(atm->bottom_radius_m + shadow_flight_level_km[i] * FM_KM, job->top);
        vec3 position = sun_frame_toward_sun(&job->observer, beta, radius);
        sun_frame f = sun_frame_at(position, job->single->sun_dir);
        double eh = -acos(fmin(1.0, atm->bottom_radius_m / radius)), sum = 0.0;
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
        job->value[(size_t)i * job->suns + j] = sum / (4.0 * FM_PI);
    }
}

/* Fills job->value (suns columns `step` apart from the observer's local sun elevation). */
static fm_status build_values(build_job *job, int threads, const atomic_int *cancel)
{
    atomic_init(&job->no_memory, 0);
    fm_status s = parallel_for(threads, (int64_t)SHADOW_FLIGHT_LEVELS * job->suns, 1, build_points, job, cancel, NULL);
    return !s && atomic_load(&job->no_memory) ? FM_ERR_OUT_OF_MEMORY : s;
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

/* The observer's local sun elevation (rad). */
static double observer_sun(const path_context *single, vec3 observer)
{
    return asin(clamp_cosine(v3_dot(v3_normalize(observer), single->sun_dir)));
}

fm_status shadow_flight_columns_build(shadow_flight_columns *c, const path_context *single, vec3 observer,
                                      double up_to, double sun_step, int threads, const atomic_int *cancel)
{
    const atmosphere *atm = single->atm;
    *c = (shadow_flight_columns){.sun0 = observer_sun(single, observer), .sun_step = sun_step};
    c->suns = (int)ceil((up_to - c->sun0) / c->sun_step) + 1;
    if (c->suns < 2)
        c->suns = 2;
    if (!(c->value = malloc(sizeof(double) * SHADOW_FLIGHT_LEVELS * (size_t)c->suns)))
        return FM_ERR_OUT_OF_MEMORY;
    build_job job = {.single = single, .top = atm->top_radius_m - 1.0, .value = c->value, .suns = c->suns,
                     .step = c->sun_step};
    job.observer = sun_frame_at(observer, single->sun_dir);
    fm_status s = build_values(&job, threads, cancel);
    if (s)
        shadow_flight_columns_free(c);
    return s;
}

void shadow_flight_columns_free(shadow_flight_columns *c)
{
    free(c->value);
    c->value = NULL;
}

/* t->value from the shared columns, geometric between them (I climbs by decades per degree across the
 * shadow), linear where one is 0; returns 0 when they do not cover t's suns. */
static int values_from_columns(shadow_flight_table *t, const shadow_flight_columns *c)
{
    if (!c || !c->value)
        return 0;
    double first = (t->sun0 - c->sun0) / c->sun_step, last = first + (SHADOW_FLIGHT_SUNS - 1) * t->sun_step / c->sun_step;
    if (first < -1e-9 || last > c->suns - 1 + 1e-9)
        return 0;
    for (int j = 0; j < SHADOW_FLIGHT_SUNS; j++) {
        double x = fmax(0.0, first + j * t->sun_step / c->sun_step);
        int k = (int)fmin(floor(x), c->suns - 2);
        double a = fmin(1.0, x - k);
        for (int i = 0; i < SHADOW_FLIGHT_LEVELS; i++) {
            double v0 = c->value[(size_t)i * c->suns + k], v1 = c->value[(size_t)i * c->suns + k + 1];
            t->value[i][j] = v0 > 0.0 && v1 > 0.0 ? v0 * pow(v1 / v0, a) : (1.0 - a) * v0 + a * v1;
        }
    }
    return 1;
}

fm_status shadow_flight_build(shadow_flight_table *t, const path_context *single, vec3 observer,
                              const shadow_flight_columns *shared, int threads, const atomic_int *cancel)
{
    const atmosphere *atm = single->atm;
    build_job job = {.t = t, .single = single, .top = atm->top_radius_m - 1.0, .value = &t->value[0][0],
                     .suns = SHADOW_FLIGHT_SUNS, .step = SHADOW_FLIGHT_SUN_STEP};
    job.observer = sun_frame_at(observer, single->sun_dir);
    t->bottom_radius = atm->bottom_radius_m;
    t->sun0 = observer_sun(single, observer);
    t->sun_step = job.step;
    for (int k = 0, i = 0; k <= SHADOW_FLIGHT_TOP_KM; k++) {
        while (i < SHADOW_FLIGHT_LEVELS - 2 && k > shadow_flight_level_km[i + 1])
            i++;
        t->level_at_km[k] = (unsigned char)i;
    }
    fm_status s = values_from_columns(t, shared) ? FM_OK : build_values(&job, threads, cancel);
    return s ? s : parallel_for(threads, SHADOW_FLIGHT_LEVELS, 1, build_ambient, &job, cancel, NULL);
}


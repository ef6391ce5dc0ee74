#include "transport/sky_guide_build.h"

#include "base/threads.h"
#include "base/units.h"
#include "spectrum/spectral_grid.h"
#include "transport/shadow_flight.h"
#include "transport/single_scatter.h"
#include "transport/sun_frame.h"

#include <math.h>
#include <stdatomic.h>

/* altitudes of the levels above the observer's (km) */
static const double level_km[SKY_GUIDE_ALTITUDES] = {0.0, 4.0, 9.0, 15.0, 22.0, 32.0, 45.0};
/* Elevation of row edge j for a level whose horizon is at elevation eh (<= 0): crowded at eh. */
static double row_elevation(int j, double eh)
{
    return sun_frame_row_elevation(j, eh, SKY_GUIDE_ROWS_DOWN, SKY_GUIDE_ROWS_UP);
}

/* A sampling density needs no more than the coarser single-scattering quadrature (single_scatter.h) */
#define GUIDE_QUADRATURE_POINTS 4

typedef struct build_job {
    sky_guide *g;
    const path_context *single;
    sun_frame observer;
    atomic_int no_memory;
    const shadow_flight_table *flights; /* or NULL: single scattering alone */
} build_job;

/* Work item: one row of one level; fills the row's cell masses (luminance x solid angle). */
static void build_rows(void *ctx, int64_t begin, int64_t end, int thread)
{
    build_job *job = ctx;
    const atmosphere *atm = job->single->atm;
    for (int64_t item = begin; item < end; item++) {
        sky_guide_level *g = &job->g->level[item / SKY_GUIDE_ROWS];
        int i = (int)(item % SKY_GUIDE_ROWS);
        double beta = sky_guide_offset_deg[g->offset] * FM_DEG;
        vec3 position = sun_frame_toward_sun(&job->observer, beta, g->radius);
        sun_frame f = sun_frame_at(position, job->single->sun_dir);
        double eh = -acos(fmin(1.0, atm->bottom_radius_m / g->radius));
        double e = 0.5 * (row_elevation(i, eh) + row_elevation(i + 1, eh));
        double omega = (sin(row_elevation(i + 1, eh)) - sin(row_elevation(i, eh))) * 2.0 * FM_PI / SKY_GUIDE_COLS;
        /* one view ray profile per row (single_scatter.h) */
        single_scatter_ray ray;
        if (single_scatter_ray_init(&ray, job->single, position, sun_frame_direction(&f, sin(e), 0.0),
                                    GUIDE_QUADRATURE_POINTS)) {
            atomic_store(&job->no_memory, 1);
            return;
        }
        /* symmetric about the sun's vertical plane: columns c and COLS - 1 - c look alike */
        for (int c = 0; c < SKY_GUIDE_COLS / 2; c++) {
            double phi = 2.0 * FM_PI * (c + 0.5) / SKY_GUIDE_COLS;
            double L[FM_MAX_WAVELENGTHS] = {0};
            vec3 d = sun_frame_direction(&f, sin(e), phi);
            single_scatter_ray_radiance(&ray, job->single, d, L);
            double y = spectral_grid_luminance(&atm->grid, L);
            if (job->flights && !g->single_only)
                y += shadow_flight_order2(job->flights, job->single, position, d);
            g->pdf[i][c] = g->pdf[i][SKY_GUIDE_COLS - 1 - c] = fmax(y, 0.0) * omega;
        }
        single_scatter_ray_free(&ray);
    }
}

/* From the cells' masses (in pdf) to the cdfs and the density per steradian. */
static int normalise_level(sky_guide_level *g)
{
    double row_mass[SKY_GUIDE_ROWS], total = 0.0;
    for (int i = 0; i < SKY_GUIDE_ROWS; i++) {
        g->cdf_col[i][0] = 0.0;
        for (int c = 0; c < SKY_GUIDE_COLS; c++)
            g->cdf_col[i][c + 1] = g->cdf_col[i][c] + g->pdf[i][c];
        row_mass[i] = g->cdf_col[i][SKY_GUIDE_COLS];
        total += row_mass[i];
    }
    if (!(total > 0.0))
        return 0;
    g->cdf_row[0] = 0.0;
    for (int i = 0; i < SKY_GUIDE_ROWS; i++) {
        double omega = (g->edge_sin[i + 1] - g->edge_sin[i]) * 2.0 * FM_PI / SKY_GUIDE_COLS;
        g->cdf_row[i + 1] = g->cdf_row[i] + row_mass[i] / total;
        for (int c = 0; c <= SKY_GUIDE_COLS; c++)
            g->cdf_col[i][c] = row_mass[i] > 0.0 ? g->cdf_col[i][c] / row_mass[i] : (double)c / SKY_GUIDE_COLS;
        for (int c = 0; c < SKY_GUIDE_COLS; c++)
            g->pdf[i][c] = omega > 0.0 ? g->pdf[i][c] / total / omega : 0.0;
    }
    g->cdf_row[SKY_GUIDE_ROWS] = 1.0;
    return 1;
}

/* Appends an empty level at this radius and offset, its rows' edges laid from its horizon. */
static void add_level(sky_guide *g, const atmosphere *atm, double radius, int offset, int single_only)
{
    sky_guide_level *l = &g->level[g->levels++];
    l->single_only = single_only;
    l->radius = radius;
    l->offset = offset;
    l->horizon = -acos(fmin(1.0, atm->bottom_radius_m / l->radius));
    for (int j = 0; j <= SKY_GUIDE_ROWS; j++)
        l->edge_sin[j] = sin(row_elevation(j, l->horizon));
}

fm_status sky_guide_build(sky_guide *g, const path_context *single, vec3 observer, int offsets, int threads,
                          const shadow_flight_table *flights, const sky_guide_extra *extra, int extras,
                          const atomic_int *cancel, int *usable)
{
    const atmosphere *atm = single->atm;
    double r0 = v3_length(observer);
    g->levels = 0;
    g->offsets = offsets < 1 ? 1 : (offsets > SKY_GUIDE_MAX_OFFSETS ? SKY_GUIDE_MAX_OFFSETS : offsets);
    g->sun0 = asin(clamp_cosine(v3_dot(observer, single->sun_dir) / r0));
    g->bottom_radius = atm->bottom_radius_m;
    g->align_horizons = 1;
    for (int o = 0; o < g->offsets; o++) {
        for (int i = 0; i < SKY_GUIDE_ALTITUDES && r0 + level_km[i] * FM_KM < atm->top_radius_m; i++)
            add_level(g, atm, r0 + level_km[i] * FM_KM, o, 0);
        for (int e = 0; e < extras && e < SKY_GUIDE_EXTRA_LEVELS; e++)
            if (extra[e].radius > atm->bottom_radius_m && extra[e].radius < atm->top_radius_m)
                add_level(g, atm, extra[e].radius, o, extra[e].single_only);
    }
    build_job job = {g, single, sun_frame_at(observer, single->sun_dir), 0, flights};
    *usable = 0;
    fm_status s = parallel_for(threads, (int64_t)g->levels * SKY_GUIDE_ROWS, 1, build_rows, &job, cancel, NULL);
    if (!s && atomic_load(&job.no_memory))
        s = FM_ERR_OUT_OF_MEMORY;
    if (s)
        return s;
    for (int i = 0; i < g->levels; i++)
        *usable |= g->level[i].usable = normalise_level(&g->level[i]);
    return FM_OK;
}


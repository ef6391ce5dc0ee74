#include "transport/sky_guide.h"

#include "base/threads.h"
#include "base/units.h"
#include "spectrum/spectral_grid.h"
#include "transport/path.h"
#include "transport/shadow_flight.h"
#include "transport/single_scatter.h"
#include "transport/sun_frame.h"

#include <math.h>
#include <stdatomic.h>

/* altitudes of the levels above the observer's (km) */
static const double level_km[SKY_GUIDE_ALTITUDES] = {0.0, 4.0, 9.0, 15.0, 22.0, 32.0, 45.0};
/* and their distances toward the sun (degrees of arc) */
static const double offset_deg[SKY_GUIDE_MAX_OFFSETS] = {0.0, 2.0, 4.0, 6.0, 9.0, 12.0};

/* Elevation of row edge j for a level whose horizon is at elevation eh (<= 0): crowded at eh. */
static double row_elevation(int j, double eh)
{
    return sun_frame_row_elevation(j, eh, SKY_GUIDE_ROWS_DOWN, SKY_GUIDE_ROWS_UP);
}

/* Index i with a[i] <= u < a[i + 1] among n bins (a ascending). */
static int find_bin(const double *a, int n, double u)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (a[mid] <= u)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
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
        double beta = offset_deg[g->offset] * FM_DEG;
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
            if (job->flights)
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

int sky_guide_build(sky_guide *g, const path_context *single, vec3 observer, int offsets, int threads,
                    const shadow_flight_table *flights, const atomic_int *cancel)
{
    const atmosphere *atm = single->atm;
    double r0 = v3_length(observer);
    g->levels = 0;
    g->offsets = offsets < 1 ? 1 : (offsets > SKY_GUIDE_MAX_OFFSETS ? SKY_GUIDE_MAX_OFFSETS : offsets);
    g->sun0 = asin(clamp_cosine(v3_dot(observer, single->sun_dir) / r0));
    g->bottom_radius = atm->bottom_radius_m;
    g->align_horizons = 1;
    for (int o = 0; o < g->offsets; o++)
        for (int i = 0; i < SKY_GUIDE_ALTITUDES && r0 + level_km[i] * FM_KM < atm->top_radius_m; i++) {
            sky_guide_level *l = &g->level[g->levels++];
            l->radius = r0 + level_km[i] * FM_KM;
            l->offset = o;
            l->horizon = -acos(fmin(1.0, atm->bottom_radius_m / l->radius));
            for (int j = 0; j <= SKY_GUIDE_ROWS; j++)
                l->edge_sin[j] = sin(row_elevation(j, l->horizon));
        }
    build_job job = {g, single, sun_frame_at(observer, single->sun_dir), 0, flights};
    if (parallel_for(threads, (int64_t)g->levels * SKY_GUIDE_ROWS, 1, build_rows, &job, cancel, NULL) ||
        atomic_load(&job.no_memory))
        return -1;
    int usable = 0;
    for (int i = 0; i < g->levels; i++)
        usable += g->level[i].usable = normalise_level(&g->level[i]);
    return usable > 0;
}

/* The level for the vertex x: the offset whose local sun is nearest x's among those with a usable
 * level, then the usable level of that offset nearest x's radius (sky_guide_build guarantees one). */
static const sky_guide_level *level_for(const sky_guide *g, vec3 x, vec3 sun_dir)
{
    double r = v3_length(x);
    int offset = 0;
    if (g->offsets > 1) {
        double beta = (asin(clamp_cosine(v3_dot(x, sun_dir) / r)) - g->sun0) / FM_DEG, gap = INFINITY;
        for (int i = 0; i < g->levels; i++)
            if (g->level[i].usable && fabs(offset_deg[g->level[i].offset] - beta) < gap) {
                gap = fabs(offset_deg[g->level[i].offset] - beta);
                offset = g->level[i].offset;
            }
    }
    int best = -1;
    for (int i = 0; i < g->levels; i++)
        if (g->level[i].usable && g->level[i].offset == offset &&
            (best < 0 || fabs(g->level[i].radius - r) < fabs(g->level[best].radius - r)))
            best = i;
    return &g->level[best];
}

/* The elevation (rad) of the horizon of a vertex at radius r, as the level's sky is laid over it
 * (sky_guide.h: lined up with the level's, unless align_horizons is 0). */
static double vertex_horizon(const sky_guide *g, const sky_guide_level *l, double r)
{
    return g->align_horizons ? -acos(fmin(1.0, g->bottom_radius / r)) : l->horizon;
}

/* The slope d(e_level) / de of the map from the elevations of a vertex whose horizon is at eh to the
 * level's, linear between the horizons and the zenith (above) or the nadir. */
static double level_slope(const sky_guide_level *l, double eh, int above)
{
    return above ? (0.5 * FM_PI - l->horizon) / (0.5 * FM_PI - eh) : (0.5 * FM_PI + l->horizon) / (0.5 * FM_PI + eh);
}

vec3 sky_guide_sample(const sky_guide *g, vec3 x, vec3 sun_dir, double u1, double u2, double u3)
{
    const sky_guide_level *l = level_for(g, x, sun_dir);
    int i = find_bin(l->cdf_row, SKY_GUIDE_ROWS, u1);
    while (i > 0 && !(l->cdf_row[i + 1] > l->cdf_row[i]))
        i--; /* never an empty row */
    int c = find_bin(l->cdf_col[i], SKY_GUIDE_COLS, u2);
    while (c > 0 && !(l->cdf_col[i][c + 1] > l->cdf_col[i][c]))
        c--;
    double v = (u2 - l->cdf_col[i][c]) / (l->cdf_col[i][c + 1] - l->cdf_col[i][c]);
    double sin_level = l->edge_sin[i] + (l->edge_sin[i + 1] - l->edge_sin[i]) * u3;
    double phi = 2.0 * FM_PI * (c + clamp_between(v, 0.0, 1.0)) / SKY_GUIDE_COLS;
    double e_level = asin(clamp_cosine(sin_level)), eh = vertex_horizon(g, l, v3_length(x));
    double slope = level_slope(l, eh, e_level >= l->horizon);
    double e = clamp_between(eh + (e_level - l->horizon) / slope, -0.5 * FM_PI, 0.5 * FM_PI);
    sun_frame f = sun_frame_at(x, sun_dir);
    return sun_frame_direction(&f, sin(e), phi);
}

double sky_guide_pdf(const sky_guide *g, vec3 x, vec3 sun_dir, vec3 d)
{
    const sky_guide_level *l = level_for(g, x, sun_dir);
    sun_frame f = sun_frame_at(x, sun_dir);
    double e = asin(clamp_cosine(v3_dot(d, f.up))), eh = vertex_horizon(g, l, v3_length(x));
    double phi = atan2(v3_dot(d, f.side), v3_dot(d, f.sun_h));
    if (phi < 0.0)
        phi += 2.0 * FM_PI;
    double slope = level_slope(l, eh, e >= eh);
    double e_level = l->horizon + (e - eh) * slope;
    /* per steradian of the vertex's sky: d(sin e_level) / d(sin e) */
    double cos_e = cos(e), jacobian = cos_e > 1e-9 ? cos(e_level) * slope / cos_e : slope * slope;
    int i = find_bin(l->edge_sin, SKY_GUIDE_ROWS, sin(e_level));
    int c = (int)(phi / (2.0 * FM_PI) * SKY_GUIDE_COLS);
    c = c < 0 ? 0 : (c >= SKY_GUIDE_COLS ? SKY_GUIDE_COLS - 1 : c);
    return l->pdf[i][c] * jacobian;
}

#include "render/fog_table.h"

#include "base/units.h"
#include "base/vec.h"
#include "render/fog_column.h"
#include "render/fog_local_sun.h"
#include "render/fog_sums.h"
#include "render/ms_table.h"
#include "render/render_job.h"
#include "sky.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void fog_table_size(quality_settings *q)
{
    q->ms_rows_sky = q->ms_rows_sky > FOG_TABLE_ROWS_SKY ? q->ms_rows_sky : FOG_TABLE_ROWS_SKY;
    q->ms_cols = q->ms_cols > FOG_TABLE_COLS ? q->ms_cols : FOG_TABLE_COLS;
}

/* The table's sums (t->sum, t->peak) and the ground's at the job's sky's sun: the column lit from
 * above (with response, where not NULL) and the day's blended by share. */
static fm_status table_sums(render_job *job, double share, fog_tables_fn tables, column_response *response,
                            double *ground, int *on_ground)
{
    ms_table *t = job->ms;
    const size_t n = (size_t)sky_grid_nodes(&t->grid) * job->sky->atm.grid.count;
    double day_ground[FM_MAX_WAVELENGTHS];
    fm_status s = FM_OK;
    double *day = NULL; /* between the thresholds: the column lit by the beam and the air, to blend */
    if (share > 0.0 && share < 1.0 && !(s = fog_column_sums(job, 0, tables, NULL, day_ground, on_ground)) &&
        (day = malloc(sizeof(double) * n)))
        memcpy(day, t->sum, sizeof(double) * n);
    else if (share > 0.0 && share < 1.0 && !s)
        s = FM_ERR_OUT_OF_MEMORY;
    if (!s)
        s = fog_column_sums(job, share > 0.0, tables, response, ground, on_ground);
    for (size_t i = 0; i < n && day && !s; i++)
        t->sum[i] = share * t->sum[i] + (1.0 - share) * day[i];
    for (int k = 0; k < job->sky->atm.grid.count && day && !s; k++)
        ground[k] = share * ground[k] + (1.0 - share) * day_ground[k];
    free(day);
    return s;
}

/* The incident skies' paths, a share of the quality's: the deck sees each through its whole sky, whose
 * noise it averages. */
#define LOCAL_SUN_PATH_SHARE 4

/* Under a thin layer the suns' shift and the views' tilt fade over FOG_TABLE_BLEND_DEG below
 * FOG_TABLE_THIN_MIN_SUN_DEG, where one sun takes the table: without the fade the map moved by 0.40 %
 * RMS (3.3 % at most) from 23.99 to 24.01 degrees under cirrostratus. */
static double thin_shift(double sun_rad)
{
    return fmin(1.0, (FOG_TABLE_THIN_MIN_SUN_DEG - sun_rad / FM_DEG) / FOG_TABLE_BLEND_DEG);
}

/* Its shift fades over FOG_TABLE_BLEND_DEG below the bound, where one sun takes the table. */
static double above_shift(double sun_rad)
{
    return fmin(1.0, (FOG_TABLE_ABOVE_LOCAL_SUN_DEG - sun_rad / FM_DEG) / FOG_TABLE_BLEND_DEG);
}

/* The regimes at several suns, under an elevated deck (FOG_REGIME_FROM_ABOVE_SUNS), a thin layer
 * (FOG_REGIME_DAY_THIN_SUNS) or above a deck (FOG_REGIME_DAY_ABOVE_SUNS): the table at the
 * suns fog_local_sun.h spans, each node's along its view.  The observer's sun goes last: the peak
 * and the ground are its.  Under a deck the shift fades with the column lit from above's share, so
 * that where the day's column (one sun) takes the table alone the views do not jump (3.4 % at the
 * horizon across 5.8 degrees under altostratus).  Under a thin layer (the day's column alone) the
 * suns are no farther apart than the observer's is above FOG_TABLE_MIN_SUN_DEG, where the day's
 * column has its beam (views beyond them take the nearest), the arcs toward the sun count
 * FOG_LOCAL_SUN_THIN_TOWARD times, and each point takes the view at its own elevation
 * (fog_local_sun.h; decks as measured before, without). */
static fm_status local_sun_sums(render_job *job, fog_regime regime, fog_tables_fn tables, double *ground, int *on_ground)
{
    const fm_sky *own = job->sky;
    const size_t n = (size_t)sky_grid_nodes(&job->ms->grid) * own->atm.grid.count;
    const double base = own->composition.cloud[fog_regime_cloud(own)].base_m;
    const double top = base + own->composition.cloud[fog_regime_cloud(own)].thickness_m;
    const double altitude = v3_length(own->observer) - own->atm.bottom_radius_m;
    const int thin = regime == FOG_REGIME_DAY_THIN_SUNS, day = regime != FOG_REGIME_FROM_ABOVE_SUNS;
    const double R = own->atm.bottom_radius_m; /* from above, the arc to the deck top's horizon */
    const double span = regime == FOG_REGIME_DAY_ABOVE_SUNS ? acos((R + top) / (R + altitude)) : fog_local_sun_span(&own->atm, base);
    const double e0 = asin(clamp_cosine(own->sun_dir.z));
    const double step = day ? fmin(span, e0 - FOG_TABLE_MIN_SUN_DEG * FM_DEG) : span;
    double *at = malloc(sizeof(double) * n * FOG_LOCAL_SUNS);
    fm_sky *local = malloc(sizeof *local); /* read alone: the same atmosphere and tables, another sun */
    /* the suns' columns lit from above share their layers (the fog's alone, no beam in them) */
    column_response response = {calloc((size_t)own->atm.grid.count * FOG_MOMENTS * job->ms->grid.rows_sky * FOG_STREAMS,
                                       sizeof(double)), 0};
    if (!at || !local || !response.values) {
        free(at);
        free(local);
        free(response.values);
        return FM_ERR_OUT_OF_MEMORY;
    }
    *local = *own;
    static const int order[FOG_LOCAL_SUNS] = {0, 2, 1};
    fm_status s = FM_OK;
    for (int j = 0; j < FOG_LOCAL_SUNS && !s; j++) {
        const double e = e0 + (order[j] - 1) * step;
        local->params.sun_elevation_deg = e / FM_DEG;
        local->sun_dir = direction_from_elevation_azimuth(e, own->params.sun_azimuth_deg * FM_DEG);
        const int paths = job->q.ms_paths;
        job->sky = order[j] == 1 ? own : local;
        job->q.ms_paths = (paths + LOCAL_SUN_PATH_SHARE - 1) / LOCAL_SUN_PATH_SHARE;
        s = table_sums(job, day ? 0.0 : fog_regime_above_share(job->sky), tables, &response, ground, on_ground);
        job->sky = own;
        job->q.ms_paths = paths;
        if (!s)
            memcpy(at + order[j] * n, job->ms->sum, sizeof(double) * n);
    }
    const double *const tables_at[FOG_LOCAL_SUNS] = {at, at + n, at + 2 * n};
    if (!s && regime == FOG_REGIME_DAY_ABOVE_SUNS)
        fog_local_sun_combine_down(&own->atm, &job->ms->grid, altitude, top, step, above_shift(e0), tables_at,
                                   job->ms->sum);
    else if (!s)
        fog_local_sun_combine(&own->atm, &job->ms->grid, base, step, thin ? thin_shift(e0) : fog_regime_above_share(own),
                              thin ? FOG_LOCAL_SUN_THIN_TOWARD : 1.0, thin ? thin_shift(e0) : 0.0, tables_at,
                              job->ms->sum);
    free(response.values);
    free(local);
    free(at);
    return s;
}

fm_status fog_table_fill(render_job *job, fog_tables_fn tables)
{
    const fm_sky *sky = job->sky;
    const atmosphere *atm = &sky->atm;
    ms_table *t = job->ms;
    const int K = atm->grid.count, nodes = sky_grid_nodes(&t->grid);
    if (t->grid.rows_sky + t->grid.rows_ground > (int)(sizeof ((fog_column *)0)->mu / sizeof(double)))
        return FM_ERR_INVALID_ARGUMENT;
    double ground[FM_MAX_WAVELENGTHS];
    int on_ground;
    const fog_regime regime = fog_regime_of(job);
    const int suns = regime == FOG_REGIME_DAY_THIN_SUNS || regime == FOG_REGIME_DAY_ABOVE_SUNS ||
                     regime == FOG_REGIME_FROM_ABOVE_SUNS;
    fm_status s = suns ? local_sun_sums(job, regime, tables, ground, &on_ground) /* at several suns */
                       : table_sums(job, fog_table_above_share(job), tables, NULL, ground, &on_ground);
    if (!s) {
        /* the nodes as one path each, already the whole of orders >= 2: no fit */
        t->paths = 1;
        for (int i = 0; i < nodes; i++) {
            const double *L = &t->sum[(size_t)i * K];
            t->y[i] = spectral_grid_luminance(&atm->grid, L);
            t->var[i] = 0.0;
            render_channels(atm, job->channels, L, &t->grid.values[(size_t)i * job->channels]);
        }
        job->paths_per_node = 0;
        if (!on_ground) { /* the ground's quadrature holds order 1 (render.c builds it without paths) */
            double order1[FM_MAX_WAVELENGTHS];
            ground_irradiance_lookup(&job->ground, sky->sun_dir.z, order1);
            for (int k = 0; k < K; k++)
                ground[k] -= order1[k];
        }
        ground_irradiance_add(&job->ground, ground);
    }
    return s;
}

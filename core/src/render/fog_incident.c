#include "render/fog_incident.h"

#include "base/rng.h"
#include "render/ms_table.h"
#include "render/render_job.h"
#include "sky.h"
#include "transport/plane_column.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Azimuths from the sun's, 0 to 180 degrees, for the field's Fourier modes: one degree apart resolves
 * the twilit sky's glow about the sun's azimuth in the modes the column keeps (24). */
#define AZIMUTHS 181
/* The field is the sky's half: the table's rows looking down only as many as its fit needs. */
#define INCIDENT_ROWS_GROUND 3
/* The share of the quality's ground paths for the light on the fog's top, which the fog's albedo
 * brings back to the field on the table's nodes over the whole sky. */
#define INCIDENT_GROUND_SHARE 4
/* The incident sky's seed, apart from the render's own streams. */
#define INCIDENT_SEED 0x66f9a1c3u

/* The tables' radiance (single scattering, and all of it) toward elevation e, azimuth phi. */
static void radiance_at(const render_job *sj, double e, double phi, float *single, float *all)
{
    float ms[FM_MAX_WAVELENGTHS];
    sky_grid_lookup(&sj->ss, e, phi, single);
    sky_grid_lookup(&sj->ms->grid, e, phi, ms);
    for (int k = 0; k < sj->channels; k++)
        all[k] = single[k] + ms[k];
}

/* The field's modes by the trapezoid rule over [0, pi] (the sky is symmetric about the sun's
 * vertical): I_m = (1 / pi) int_0^pi L(phi) cos(m phi) dphi. */
static void field_modes(const render_job *sj, fog_incident *f)
{
    const int K = f->K, S = f->streams, M = f->modes;
    double mu[64];
    plane_column_nodes(S, mu);
    memset(f->field, 0, sizeof(double) * (size_t)K * S * M);
    for (int j = 0; j < S; j++)
        for (int a = 0; a < AZIMUTHS; a++) {
            const double phi = FM_PI * a / (AZIMUTHS - 1.0), w = (a == 0 || a == AZIMUTHS - 1 ? 0.5 : 1.0) / (AZIMUTHS - 1.0);
            float single[FM_MAX_WAVELENGTHS], all[FM_MAX_WAVELENGTHS];
            radiance_at(sj, asin(mu[j]), phi, single, all);
            for (int m = 0; m < M; m++) {
                const double c = w * cos(m * phi);
                for (int k = 0; k < K; k++)
                    f->field[((size_t)k * S + j) * M + m] += c * all[k];
            }
        }
}

/* The sky without the fog and its fast tables (the caller's job sj, with its table ms). */
static fm_status incident_tables(const render_job *job, fog_tables_fn tables, fm_sky *sub, fm_render_params *sp,
                                 render_job *sj, ms_table *ms, twilight_sampling **tw)
{
    *sp = *job->params;
    sp->spectral = 1;
    sp->progress = NULL;
    *sj = (render_job){.sky = sub, .params = sp, .ms = ms, .q = job->q, .cam = job->cam,
                       .seed = mix64(job->seed ^ INCIDENT_SEED), .channels = sub->atm.grid.count, .one_pass = 1};
    sj->q.ms_rows_ground = INCIDENT_ROWS_GROUND;
    sj->q.ground_paths = (job->q.ground_paths + INCIDENT_GROUND_SHARE - 1) / INCIDENT_GROUND_SHARE;
    return tables(sj, tw);
}

fm_status fog_incident_build(const render_job *job, fog_tables_fn tables, int cloud, double fog_top_m, const double *albedo, int streams,
                             int modes, const sky_grid *nodes, fog_incident *out)
{
    const int K = job->sky->atm.grid.count, n = nodes->rows_sky * nodes->cols;
    *out = (fog_incident){.K = K, .streams = streams, .modes = modes};
    if (streams > 64)
        return FM_ERR_INVALID_ARGUMENT;
    out->field = malloc(sizeof(double) * ((size_t)K * streams * modes + 2 * (size_t)n * K));
    if (!out->field)
        return FM_ERR_OUT_OF_MEMORY;
    out->seen = out->field + (size_t)K * streams * modes;
    out->single = out->seen + (size_t)n * K;
    fm_sky *sub = NULL;
    fm_error err = {0};
    fm_status s = sky_create_without_cloud(job->sky, cloud, fog_top_m, &sub, &err);
    if (s)
        return s;
    for (int k = 0; k < K; k++)
        sub->atm.ground_albedo[k] = albedo[k];
    fm_render_params sp;
    ms_table ms = {0};
    render_job sj;
    twilight_sampling *tw = NULL;
    if (!(s = incident_tables(job, tables, sub, &sp, &sj, &ms, &tw))) {
        field_modes(&sj, out);
        for (int i = 0; i < n; i++) {
            double e, phi;
            float single[FM_MAX_WAVELENGTHS], all[FM_MAX_WAVELENGTHS];
            sky_grid_node_angles(nodes, i, &e, &phi);
            radiance_at(&sj, e, phi, single, all);
            for (int k = 0; k < K; k++) {
                out->seen[(size_t)i * K + k] = all[k];
                out->single[(size_t)i * K + k] = single[k];
            }
        }
    }
    free(tw);
    sky_grid_free(&sj.ss);
    ms_table_free(&ms);
    ground_irradiance_free(&sj.ground);
    deck_base_free(&sj.deck);
    fm_sky_destroy(sub);
    return s;
}

void fog_incident_free(fog_incident *f)
{
    free(f->field);
    *f = (fog_incident){0};
}

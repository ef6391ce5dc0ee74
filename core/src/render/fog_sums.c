#include "render/fog_sums.h"

#include "base/threads.h"
#include "render/fog_peak.h"
#include "render/fog_regime.h"
#include "render/ms_table.h"
#include "render/render_job.h"
#include "sky.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Single scattering at the bottom looking up along mu, per unit F0, from one homogeneous layer of
 * optical depth tau lit at its top, with albedo times phase function ssa_phase. */
static double single_bottom(double tau, double ssa_phase, double mu, double mu0)
{
    const double d = mu - mu0;
    const double f = fabs(d) < 1e-12 ? tau / (mu * mu0) * exp(-tau / mu0) : (exp(-tau / mu) - exp(-tau / mu0)) / d;
    return ssa_phase * mu0 * f;
}

/* Single scattering looking down along mu from the top of one homogeneous layer lit at its top,
 * per unit F0 (as single_bottom). */
static double single_top(double tau, double ssa_phase, double mu, double mu0)
{
    return ssa_phase * mu0 / (mu + mu0) * -expm1(-tau * (mu + mu0) / (mu * mu0));
}

/* The column's radiance at one node from its Fourier modes, less the part of its order 1 that is
 * order 1 (one scattering by the truncated phase function, at the true optical depths; the rest of
 * the scaled order 1 was also scattered within the peak): the single-scattering table holds it.
 * Looking up (down 0) the layers above the observer scatter it, looking down those below. */
static double node_radiance(const fog_column *fc, const scaled_layer *sl, const plane_layer *pl, const double *above,
                            const double *modes, double mu, double phi, double mu_sun, int down)
{
    double L = modes[0];
    for (int m = 1; m < FOG_MOMENTS; m++)
        L += 2.0 * modes[m] * cos(m * phi);
    double between = 0.0; /* optical depth from the layer to the observer */
    for (int l = down ? fc->level : fc->level - 1; down ? l < fc->layers : l >= 0; l += down ? 1 : -1) {
        const double mu0 = pl[l].mu0 > 0.0 ? pl[l].mu0 : mu_sun; /* the layer's beam, as the column's */
        const double x = (down ? -mu : mu) * mu0 + sqrt(fmax(0.0, (1.0 - mu * mu) * (1.0 - mu0 * mu0))) * cos(phi);
        const double sp = sl[l].ssa * (1.0 - sl[l].f) * fog_scaled_phase(sl[l].chi, x);
        L -= exp(-above[l] / mu_sun - between / mu) *
             (down ? single_top(sl[l].tau, sp, mu, mu0) : single_bottom(sl[l].tau, sp, mu, mu0));
        between += sl[l].tau;
    }
    return L;
}


/* The light from above (fc->incident) at the sky nodes at wavelength k added to the table's sums: the
 * light the fog and the ground scatter, and the field seen through the fog along the view less its
 * single scattering seen so (the single-scattering table's).  The field's scatterings within the
 * droplets' truncated peak go with it through the scaled optical depth (it is smooth over their few
 * degrees).  work: n_mu x FOG_MOMENTS.  Nonzero: no memory. */
static int diffuse_nodes(const fog_column *fc, const scaled_layer *sl, const plane_layer *pl, int k, double *work)
{
    const fog_incident *in = fc->incident;
    ms_table *t = fc->job->ms;
    const int K = in->K, M = FOG_MOMENTS, cols = t->grid.cols, rows = t->grid.rows_sky;
    plane_column col = {.streams = FOG_STREAMS, .layer_count = fc->layers, .layer = pl,
                        .ground_albedo = fc->job->sky->atm.ground_albedo[k], .mu0 = 1.0, .n_mu = rows, .mu = fc->mu};
    const double *field = in->field + (size_t)k * FOG_STREAMS * M;
    if (fc->response) {
        const int N = FOG_STREAMS;
        double *map = fc->response->values + (size_t)k * M * rows * N;
        if (!fc->response->ready && plane_column_diffuse_response(&col, fc->level, map))
            return 1;
        for (int r = 0; r < rows; r++)
            for (int m = 0; m < M; m++) {
                const double *row = map + ((size_t)m * rows + r) * N;
                double sum = 0.0;
                for (int j = 0; j < N; j++)
                    sum += row[j] * field[j * M + m];
                work[r * M + m] = sum;
            }
    } else if (plane_column_diffuse_level(&col, fc->level, field, work, NULL, NULL)) {
        return 1;
    }
    double scaled = 0.0, depth = 0.0;
    for (int l = 0; l < fc->level; l++) {
        scaled += pl[l].tau;
        depth += sl[l].tau;
    }
    for (int i = 0; i < rows * cols; i++) {
        double e, phi;
        sky_grid_node_angles(&t->grid, i, &e, &phi);
        const double *modes = work + (size_t)(i / cols) * M, mu = fc->mu[i / cols];
        double L = modes[0];
        for (int m = 1; m < M; m++)
            L += 2.0 * modes[m] * cos(m * phi);
        L += exp(-scaled / mu) * in->seen[(size_t)i * K + k] - exp(-depth / mu) * in->single[(size_t)i * K + k];
        t->sum[(size_t)i * K + k] += L;
    }
    return 0;
}

/* Work item: the table's sums at one grid wavelength. */
static void wavelength_nodes(void *ctx, int64_t begin, int64_t end, int thread)
{
    fog_column *fc = ctx;
    render_job *job = fc->job;
    const fm_sky *sky = job->sky;
    const atmosphere *atm = &sky->atm;
    ms_table *t = job->ms;
    const int K = atm->grid.count, M = FOG_MOMENTS, cols = t->grid.cols, rows = t->grid.rows_sky;
    /* the beam: none with the sun at or below the horizon (the light from above alone; mu0 then
     * stands in for the beam's cosine in what the beam's nil scale takes out) */
    const int beam = sky->sun_dir.z > 0.0;
    const double mu0 = beam ? sky->sun_dir.z : 1.0;
    (void)thread;
    for (int64_t k = begin; k < end; k++) {
        scaled_layer sl[PLANE_COLUMN_MAX_LAYERS];
        plane_layer pl[PLANE_COLUMN_MAX_LAYERS];
        double above[PLANE_COLUMN_MAX_LAYERS + 1], above_fog = 0.0;
        above[0] = 0.0;
        for (int l = 0; l < fc->layers; l++)
            fog_layer_at(fc, atm, l, (int)k, &sl[l], &pl[l]);
        if (beam)
            fog_air_beam_cosines(fc, sky, (int)k, sl, pl);
        for (int l = 0; l < fc->layers; l++) {
            const double mu_l = pl[l].mu0 > 0.0 ? pl[l].mu0 : mu0; /* the beam's depth: tau mu0 / mu_l */
            above[l + 1] = above[l] + sl[l].tau * mu0 / mu_l;
            if (l < fc->layers - fc->fog_layers)
                above_fog += sl[l].tau * mu0 / mu_l;
        }
        plane_column col = {.streams = FOG_STREAMS, .layer_count = fc->layers, .layer = pl,
                            .ground_albedo = atm->ground_albedo[k], .mu0 = mu0,
                            .n_mu = fc->on_ground ? rows : fc->n_mu, .mu = fc->mu}; /* on the ground: the views up */
        double *down = calloc((size_t)(2 * fc->n_mu * M), sizeof(double)), *up = down + fc->n_mu * M, ground;
        if (!down || (beam && plane_column_level(&col, fc->level, down, fc->on_ground ? NULL : up, NULL)) ||
            (!fc->on_ground && plane_column_level(&col, fc->layers, NULL, NULL, &ground))) {
            free(down);
            atomic_store(&job->no_memory, 1);
            return;
        }
        /* the beam at the fog's top the sun table's (the layers' cosines make it so but for the
         * table's interpolation) */
        double T_sph[FM_MAX_WAVELENGTHS] = {0};
        if (beam)
            sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, fc->top_radius, mu0, T_sph);
        const double scale = atm->grid.solar_irradiance[k] * T_sph[k] / exp(-above_fog / mu0);
        if (fog_peak_light(fc, sl, pl, (int)k, exp(-above[fc->level] / mu0) * scale)) {
            free(down);
            atomic_store(&job->no_memory, 1);
            return;
        }
        const double *rest = t->peak + (size_t)K * FOG_PEAK_ANGLES;
        for (int r = 0; r < (scale > 0.0 ? rows + (fc->on_ground ? 0 : t->grid.rows_ground) : 0); r++)
            for (int c = 0; c < cols; c++) {
                double e, phi;
                sky_grid_node_angles(&t->grid, r * cols + c, &e, &phi);
                const int looking_down = r >= rows;
                double L = node_radiance(fc, sl, pl, above, (looking_down ? up : down) + r * M, fc->mu[r], phi, mu0,
                                         looking_down);
                /* looking down: less the ground's light the single-scattering table reflects (the
                 * column's irradiance there, all of it, seen through the air below) */
                if (looking_down)
                    L -= atm->ground_albedo[k] / FM_PI * mu0 * ground * exp(-(above[fc->layers] - above[fc->level]) / fc->mu[r]);
                else /* the peak's light: its smooth negative part */
                {
                    const vec3 d = render_view_direction(sky, e, phi);
                    L += fog_peak_at(rest, (int)k, v3_dot(d, sky->sun_dir)) *
                         fog_peak_view_at(t->peak, K, (int)k, d.z) / scale;
                }
                t->sum[(size_t)(r * cols + c) * K + k] = L * scale;
            }
        /* above the ground, its diffuse irradiance comes from the column (the peak's light in it): all
         * of it but the direct beam and order 1, which the ground's own quadrature holds */
        if (!fc->on_ground)
            fc->ground[k] = scale * mu0 * (ground - exp(-above[fc->layers] / mu0));
        if (fc->incident && diffuse_nodes(fc, sl, pl, (int)k, down)) {
            free(down);
            atomic_store(&job->no_memory, 1);
            return;
        }
        free(down);
    }
}

fm_status fog_column_sums(render_job *job, int from_above, fog_tables_fn tables, column_response *response,
                             double *ground, int *on_ground)
{
    const fm_sky *sky = job->sky;
    const atmosphere *atm = &sky->atm;
    ms_table *t = job->ms;
    const int K = atm->grid.count, nodes = sky_grid_nodes(&t->grid);
    fog_column *fc = calloc(1, sizeof *fc);
    if (!fc)
        return FM_ERR_OUT_OF_MEMORY;
    fc->job = job;
    const int cloud = fog_regime_cloud(sky);
    const double base = sky->composition.cloud[cloud].base_m;
    double fog_top = base + sky->composition.cloud[cloud].thickness_m;
    if (from_above) {
        /* the layer and the air under it: its droplets thin out to the profile's next node above its
         * top (the layer's density is half at its top node, cloud_layer.c), a sixteenth of the optical
         * depth of fog 200 m deep */
        fog_column_layers(fc, sky, fmax(base, 0.0), fog_top, fog_top + FM_PROFILE_SPACING_M);
        fog_top += FM_PROFILE_SPACING_M;
        fc->fog_layers = fc->layers; /* the beam as the sun table has it at the column's top */
    } else {
        fog_column_layers(fc, sky, fmax(base, 0.0), fog_top, atm->top_radius_m - atm->bottom_radius_m);
    }
    fc->top_radius = atm->bottom_radius_m + fog_top;
    fog_view_cosines(fc, &t->grid);
    if (fc->level <= fc->layers - fc->fog_layers) /* the observer above the layer */
        fog_sphere_sky_cosines(fc, sky, &t->grid);
    fm_status s = fog_species_moments(fc, atm);
    fog_incident incident = {0};
    if (!s && from_above) {
        double albedo[FM_MAX_WAVELENGTHS];
        s = fog_albedo(fc, albedo);
        if (!s)
            s = fog_incident_build(job, tables, cloud, fog_top, albedo, FOG_STREAMS, FOG_MOMENTS, &t->grid, &incident);
        fc->incident = &incident;
        fc->response = response;
    }
    free(t->peak);
    if (!s && !(t->peak = calloc(FOG_PEAK_SIZE(K), sizeof(double))))
        s = FM_ERR_OUT_OF_MEMORY;
    if (!s) {
        memset(t->sum, 0, sizeof(double) * (size_t)nodes * K);
        const fm_render_params *p = job->params;
        parallel_progress pp = {p->progress, p->progress_user, "multiple scattering (fog column)", 0.05, 0.75};
        s = parallel_for(p->threads, K, 1, wavelength_nodes, fc, p->cancel, &pp);
        if (!s && atomic_load(&job->no_memory))
            s = FM_ERR_OUT_OF_MEMORY;
        if (!s && fc->response)
            fc->response->ready = 1;
    }
    memcpy(ground, fc->ground, sizeof(double) * (size_t)K);
    *on_ground = fc->on_ground;
    fog_incident_free(&incident);
    free(fc->chi);
    free(fc);
    return s;
}

#include "render/ms_table.h"

#include "base/rng.h"
#include "base/threads.h"
#include "base/units.h"
#include "render/render_job.h"
#include "transport/next_order_shape.h"
#include "transport/sky_grid_fit.h"
#include "transport/sky_grid_refine.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the table's memory ---------------------------------------------------------------------- */

/* Hands out the next n doubles of the block. */
static double *take(double **next, size_t n)
{
    double *p = *next;
    *next += n;
    return p;
}

fm_status ms_table_init(ms_table *t, const quality_settings *q, double horizon, int channels, int K, int parted,
                        int chroma)
{
    memset(t, 0, sizeof *t);
    /* the noisy orders are not interpolated in log space: the logarithm of a noisy mean is biased */
    if (sky_grid_init(&t->grid, horizon, q->ms_rows_sky, q->ms_rows_ground, q->ms_cols, channels, 0) ||
        (parted && sky_grid_init(&t->later, horizon, q->ms_rows_sky, q->ms_rows_ground, q->ms_cols, channels, 0))) {
        ms_table_free(t);
        return FM_ERR_OUT_OF_MEMORY;
    }
    const size_t n = (size_t)sky_grid_nodes(&t->grid);
    /* per node: y, var, shape and K sums; parted: later_y, later_var and K later sums; chroma: 4 ratios */
    const size_t per_node = 3 + (size_t)K + (parted ? 2 + (size_t)K : 0) + (chroma ? 4 : 0);
    t->block = calloc(n * per_node, sizeof(double));
    t->moments = calloc(n, sizeof *t->moments);
    t->orders = parted ? calloc(n, sizeof *t->orders) : NULL;
    if (!t->block || !t->moments || (parted && !t->orders)) {
        ms_table_free(t);
        return FM_ERR_OUT_OF_MEMORY;
    }
    double *next = t->block;
    t->y = take(&next, n);
    t->var = take(&next, n);
    t->shape = take(&next, n);
    t->sum = take(&next, n * K);
    if (parted) {
        t->later_y = take(&next, n);
        t->later_var = take(&next, n);
        t->later_sum = take(&next, n * K);
        for (size_t i = 0; i < n; i++)
            t->orders[i].later = &t->later_sum[i * K];
    }
    for (int c = 0; c < 2 && chroma; c++) {
        t->ratio[c] = take(&next, n);
        t->ratio_var[c] = take(&next, n);
    }
    return FM_OK;
}

void ms_table_free(ms_table *t)
{
    sky_grid_free(&t->grid);
    sky_grid_free(&t->later);
    free(t->block);
    free(t->moments);
    free(t->orders);
    free(t->peak);
    memset(t, 0, sizeof *t);
}

int ms_table_parted(const twilight_sampling *tw)
{
    return !tw || !tw->deep;
}

/* ---- the paths ------------------------------------------------------------------------------- */

/* Whether the table's paths take the sunlight of every rising segment as its expected value along
 * the segment (SEGMENT_SUNLIGHT_RISING; twilight has every segment).  With a low sun behind thick
 * haze the air around the observer lies in the haze's own shadow and its light comes from the sunlit
 * air above, which few paths reach by scattering there; the integral along each climbing segment
 * counts it for every path.  It pays for its cost only with the sun low and dimmed:
 * docs/decisions/2026-12-06-path-sampling.md */
#define RISING_SUN_DEG 4.5
#define RISING_BELOW 1e-3 /* the sun's transmittance to the observer at the grid's middle wavelength */
static int rising_segments(const fm_sky *sky, const twilight_sampling *twilight)
{
    if (twilight)
        return 0;
    const path_context pc = sky_path_context(sky, 1, 1);
    double r = v3_length(sky->observer), mu_s = v3_dot(sky->observer, sky->sun_dir) / r, T[FM_MAX_WAVELENGTHS];
    /* mu_s = 0 included: a sun on the horizon (the live sky's node at 0 degrees) takes no twilight
     * sampling either, and its paths without these segments are 2.5 times as noisy (the decision record
     * 2026-12-07-live-sun-on-the-horizon.md) */
    if (!(mu_s >= 0.0 && asin(clamp_cosine(mu_s)) < RISING_SUN_DEG * FM_DEG))
        return 0; /* a higher sun, or night (no twilight sampling: a black sky) */
    sun_irradiance_lookup(pc.sun_table, &sky->atm, pc.sun, r, mu_s, T);
    assert(T[sky->atm.grid.count / 2] >= 0.0 && T[sky->atm.grid.count / 2] <= 1.0); /* a transmittance */
    return T[sky->atm.grid.count / 2] < RISING_BELOW;
}

/* Item numbers of deep twilight's extra paths: after the nodes' own. */
#define ITEM_MS_EXTRA 0x80000000ull

/* One pass over the table's nodes: `paths` more paths per node, the second pass's (extra) going on
 * where the first ended. */
typedef struct node_pass {
    render_job *job;
    int extra, paths;
} node_pass;

/* Work item: one node of the table, the pass's paths added to its sums. */
static void node_paths(void *ctx, int64_t begin, int64_t end, int thread)
{
    const node_pass *pass = ctx;
    render_job *job = pass->job;
    ms_table *t = job->ms;
    const fm_sky *sky = job->sky;
    const int K = sky->atm.grid.count;
    path_context pc = scattering_path_context(sky, job->twilight, 2, 0);
    pc.skip_ground_first = 1;
    pc.deck = job->under_deck;
    if (t->rising_segments)
        pc.segment_sunlight = SEGMENT_SUNLIGHT_RISING;
    for (int64_t i = begin; i < end; i++) {
        double e, phi;
        sky_grid_node_angles(&t->grid, (int)i, &e, &phi);
        vec3 d = render_view_direction(sky, e, phi);
        /* the hero wavelengths go round the grid; the extra paths go on where the first pass ended */
        uint64_t offset = mix64(job->seed ^ (uint64_t)i) + (pass->extra ? (uint64_t)job->q.ms_paths : 0);
        uint64_t item = ITEM_MS_NODE + (pass->extra ? ITEM_MS_EXTRA : 0) + (uint64_t)i;
        table_node_paths(sky, &pc, d, pass->paths, job->seed, item, (int)(offset % (uint64_t)K), &t->sum[i * K],
                         &t->moments[i], pass->extra ? NULL : &t->shape[i], t->orders ? &t->orders[i] : NULL);
    }
}

/* One pass over the nodes of several tables that share their walks (ms_table_fill_shared). */
typedef struct shared_pass {
    render_job *const *jobs;
    int count;
    vec3 suns[PATH_SUNS_MAX];
} shared_pass;

/* Work item: one node of every table of the pass, from one set of walks (the first table's seed)
 * scored for every table's sun. */
static void shared_node_paths(void *ctx, int64_t begin, int64_t end, int thread)
{
    const shared_pass *pass = ctx;
    const render_job *first = pass->jobs[0];
    const fm_sky *sky = first->sky;
    const int K = sky->atm.grid.count;
    (void)thread;
    path_context pc = scattering_path_context(sky, NULL, 2, 0);
    pc.skip_ground_first = 1;
    /* the umbra's estimator would depend on the sun; the first sun's rising segments may take theirs */
    pc.segment_sunlight = first->ms->rising_segments ? SEGMENT_SUNLIGHT_RISING : SEGMENT_SUNLIGHT_NONE;
    pc.suns = pass->count;
    pc.sun_dirs = pass->suns;
    for (int64_t i = begin; i < end; i++) {
        double e, phi;
        sky_grid_node_angles(&first->ms->grid, (int)i, &e, &phi);
        vec3 d = render_view_direction(sky, e, phi); /* every table's: their suns share an azimuth */
        node_sums out[PATH_SUNS_MAX];
        for (int s = 0; s < pass->count; s++) {
            ms_table *t = pass->jobs[s]->ms;
            out[s] = (node_sums){&t->sum[i * K], &t->moments[i], &t->orders[i]};
        }
        uint64_t offset = mix64(first->seed ^ (uint64_t)i);
        double shape;
        table_node_paths_suns(sky, &pc, d, first->q.ms_paths, first->seed, ITEM_MS_NODE + (uint64_t)i,
                              (int)(offset % (uint64_t)K), out, &shape);
        for (int s = 0; s < pass->count; s++)
            pass->jobs[s]->ms->shape[i] = shape;
    }
}

/* A luminance's variance of the mean over n paths from the sum of its squares over them, yy. */
static double variance_of_mean(double yy, double y, double n)
{
    return n > 1.0 ? fmax(0.0, yy / n - y * y) / (n - 1.0) : 0.0;
}

/* The table's nodes from their sums over `paths` paths each: estimates, luminance variances and, at
 * twilight in colour, the chromaticity ratios and their variances; when parted, order 2 in grid and
 * the orders above in later. */
static void finish_nodes(render_job *job, int paths)
{
    ms_table *t = job->ms;
    const fm_sky *sky = job->sky;
    const int K = sky->atm.grid.count, nodes = sky_grid_nodes(&t->grid);
    const double n = paths;
    t->paths = paths;
    for (int i = 0; i < nodes; i++) {
        double L[FM_MAX_WAVELENGTHS];
        for (int k = 0; k < K; k++)
            L[k] = t->sum[i * K + k] / n;
        double yy = t->moments[i].yy; /* the whole's, or order 2's once parted */
        if (t->orders) {
            double later[FM_MAX_WAVELENGTHS];
            for (int k = 0; k < K; k++) {
                later[k] = t->later_sum[i * K + k] / n;
                L[k] -= later[k];
            }
            double y3 = spectral_grid_luminance(&sky->atm.grid, later);
            t->later_y[i] = y3;
            t->later_var[i] = variance_of_mean(t->orders[i].yy[1], y3, n);
            render_channels(&sky->atm, job->channels, later, &t->later.values[i * job->channels]);
            yy = t->orders[i].yy[0];
        }
        double y = spectral_grid_luminance(&sky->atm.grid, L);
        t->y[i] = y;
        t->var[i] = variance_of_mean(yy, y, n);
        for (int c = 0; c < 2 && t->ratio[0]; c++)
            node_moments_ratio(&t->moments[i], 2 * c, &t->ratio[c][i], &t->ratio_var[c][i]);
        render_channels(&sky->atm, job->channels, L, &t->grid.values[i * job->channels]);
    }
}

/* Deep twilight's final maps aim at a noise, not only at a number of paths: once the first pass is
 * done, the sky nodes' relative standard error (root mean square over the nodes, one number for the
 * whole table, which a node's own first paths hardly sway) is measured, and if a second pass of at
 * least a quarter more paths would bring it to DEEP_NODE_NOISE (divided by the square root of the
 * sample scale), that pass runs, with at most DEEP_EXTRA_MAX times the first pass's paths (falling
 * to none from sun -18 to -21 degrees: paths_before_night).  Haze makes the paths noisier and the
 * fit gains less on them: docs/decisions/2026-12-06-twilight-sampling.md */
#define DEEP_NODE_NOISE 0.05
#define DEEP_EXTRA_MAX 3.0
static int may_add_deep_twilight_paths(const render_job *job)
{
    return job->twilight && job->twilight->deep && job->params->quality == FM_QUALITY_FINAL && !job->one_pass;
}

double ms_table_sky_node_noise(const ms_table *t)
{
    const int nodes = t->grid.rows_sky * t->grid.cols;
    double sum = 0.0;
    int used = 0;
    for (int i = 0; i < nodes; i++)
        if (t->y[i] > 0.0) {
            sum += t->var[i] / (t->y[i] * t->y[i]);
            used++;
        }
    return used ? sqrt(sum / used) : 0.0;
}

static int deep_twilight_extra_paths(const render_job *job, double sample_scale, double sun_elevation_deg)
{
    if (!may_add_deep_twilight_paths(job))
        return 0;
    const double most = DEEP_EXTRA_MAX * paths_before_night(sun_elevation_deg);
    double noise = ms_table_sky_node_noise(job->ms), target = DEEP_NODE_NOISE / sqrt(sample_scale);
    if (noise == 0.0)
        return 0;
    assert(most >= 0.0 && most <= DEEP_EXTRA_MAX);
    double more = fmin((noise / target) * (noise / target) - 1.0, most);
    /* a pass of less than a quarter more would take the noise down by less than a tenth */
    return more > 0.25 ? (int)ceil(more * job->q.ms_paths) : 0;
}

fm_status ms_table_fill(render_job *job, double sun_elevation_deg)
{
    const fm_render_params *params = job->params;
    ms_table *t = job->ms;
    t->rising_segments = rising_segments(job->sky, job->twilight);
    /* where more paths may follow, the first pass reports half the stage */
    parallel_progress first = {params->progress, params->progress_user, "multiple scattering", 0.05, 0.75};
    parallel_progress more = first;
    if (may_add_deep_twilight_paths(job)) {
        first.span = more.span = first.span / 2.0;
        more.start = first.start + first.span;
        more.stage = "multiple scattering (more paths)";
    }
    const int nodes = sky_grid_nodes(&t->grid);
    node_pass pass = {job, 0, job->q.ms_paths};
    fm_status s = parallel_for(params->threads, nodes, 1, node_paths, &pass, params->cancel, &first);
    if (s)
        return s;
    finish_nodes(job, job->q.ms_paths);
    job->paths_per_node = job->q.ms_paths;
    int extra = deep_twilight_extra_paths(job, params->sample_scale, sun_elevation_deg);
    if (!extra)
        return FM_OK;
    pass = (node_pass){job, 1, extra};
    if ((s = parallel_for(params->threads, nodes, 1, node_paths, &pass, params->cancel, &more)))
        return s;
    finish_nodes(job, job->q.ms_paths + extra);
    job->paths_per_node = job->q.ms_paths + extra;
    return FM_OK;
}

void ms_table_add(render_job *job, const ms_table *more)
{
    ms_table *t = job->ms;
    const int K = job->sky->atm.grid.count, nodes = sky_grid_nodes(&t->grid);
    assert(!t->orders == !more->orders && nodes == sky_grid_nodes(&more->grid) && !t->ratio[0] == !more->ratio[0]);
    for (int i = 0; i < nodes; i++) {
        for (int k = 0; k < K; k++)
            t->sum[i * K + k] += more->sum[i * K + k];
        node_moments *m = &t->moments[i];
        m->yy += more->moments[i].yy;
        for (int b = 0; b < NODE_BATCHES; b++)
            for (int c = 0; c < 3; c++)
                m->batch_xyz[b][c] += more->moments[i].batch_xyz[b][c];
        t->shape[i] = more->shape[i]; /* deep twilight's view rays; a parted table's fit makes its own */
        if (t->orders) { /* the orders above 2: a part of `sum` kept apart too */
            for (int k = 0; k < K; k++)
                t->later_sum[i * K + k] += more->later_sum[i * K + k];
            t->orders[i].yy[0] += more->orders[i].yy[0];
            t->orders[i].yy[1] += more->orders[i].yy[1];
        }
    }
    finish_nodes(job, t->paths + more->paths);
    job->paths_per_node = t->paths;
}

int ms_table_walk_shareable(const render_job *job)
{
    return !job->twilight && !job->under_deck;
}

int ms_table_walk_rising(const render_job *job)
{
    return rising_segments(job->sky, job->twilight);
}

fm_status ms_table_fill_shared(render_job *const *jobs, int count)
{
    shared_pass pass = {.jobs = jobs, .count = count};
    const render_job *first = jobs[0];
    assert(count >= 1 && count <= PATH_SUNS_MAX);
    for (int s = 0; s < count; s++) {
        assert(ms_table_walk_shareable(jobs[s]) && jobs[s]->ms->orders && jobs[s]->q.ms_paths == first->q.ms_paths &&
               jobs[s]->seed == first->seed && sky_grid_nodes(&jobs[s]->ms->grid) == sky_grid_nodes(&first->ms->grid));
        pass.suns[s] = jobs[s]->sky->sun_dir;
        jobs[s]->ms->rising_segments = s == 0 && ms_table_walk_rising(jobs[s]);
        assert(s == 0 || !ms_table_walk_rising(jobs[s]));
    }
    fm_status s = parallel_for(first->params->threads, sky_grid_nodes(&first->ms->grid), 1, shared_node_paths, &pass,
                               first->params->cancel, NULL);
    for (int j = 0; j < count && !s; j++) {
        finish_nodes(jobs[j], first->q.ms_paths);
        jobs[j]->paths_per_node = first->q.ms_paths;
    }
    return s;
}

/* The sky nodes' spectra (the sums over the paths) read through sky_grid_refine by `factor`, into
 * E: the integral of the refined table (the ground rows stay 0: not integrated). */
static fm_status refined_irradiance(const ms_table *t, int K, int factor, double *E)
{
    sky_grid coarse, fine = {0};
    if (sky_grid_init(&coarse, t->grid.horizon_elevation, t->grid.rows_sky, t->grid.rows_ground, t->grid.cols, K, 0))
        return FM_ERR_OUT_OF_MEMORY;
    const int n = t->grid.rows_sky * t->grid.cols;
    for (size_t i = 0; i < (size_t)n * (size_t)K; i++)
        coarse.values[i] = (float)(t->sum[i] / t->paths);
    fm_status s = sky_grid_refine(&coarse, factor, &fine);
    sky_grid_free(&coarse);
    const int m = fine.rows_sky * fine.cols;
    double *w = s ? NULL : malloc(sizeof(double) * (size_t)m);
    if (!s && !w)
        s = FM_ERR_OUT_OF_MEMORY;
    if (!s) {
        sky_grid_irradiance_weights(&fine, w);
        for (int i = 0; i < m; i++)
            for (int k = 0; k < K; k++)
                E[k] += w[i] * fine.values[(size_t)i * K + k];
    }
    free(w);
    sky_grid_free(&fine);
    return s;
}

/* Observer on the ground: the diffuse irradiance of orders >= 2 there is the integral of the
 * table's sky half times cos(zenith), since its upward nodes estimate exactly that radiance (no
 * ground between the observer and the air), from many more paths than the ground's own:
 * docs/decisions/2026-12-06-ground-from-table.md.  The raw nodes, not the fit: the sum is linear in
 * them and no fit is needed to make it smooth. */
fm_status ms_table_add_to_ground(render_job *job)
{
    const ms_table *t = job->ms;
    const int K = job->sky->atm.grid.count, n = t->grid.rows_sky * t->grid.cols;
    double E[FM_MAX_WAVELENGTHS] = {0};
    if (job->ms_refine > 1) {
        fm_status s = refined_irradiance(t, K, job->ms_refine, E);
        if (s)
            return s;
        ground_irradiance_add(&job->ground, E);
        return FM_OK;
    }
    double *w = malloc(sizeof(double) * (size_t)n);
    if (!w)
        return FM_ERR_OUT_OF_MEMORY;
    sky_grid_irradiance_weights(&t->grid, w);
    for (int i = 0; i < n; i++)
        for (int k = 0; k < K; k++)
            E[k] += w[i] * (t->sum[(size_t)i * K + k] / t->paths);
    free(w);
    ground_irradiance_add(&job->ground, E);
    return FM_OK;
}

/* ---- the fit --------------------------------------------------------------------------------- */

/* The field that a table part's shape scatters once more (next_order_shape.h): the single-scattering
 * table (order 2's shape) or, above the horizon, the fitted order-2 table (the shape of the orders
 * above), in the channel nearest the middle grid wavelength (luminance in colour). */
typedef struct shape_field {
    const render_job *job;
    const sky_grid *above; /* the table read above the horizon; the single-scattering table below */
    int channel;
    const double *sun_field; /* the field at the shape's points about the sun (next_order_sun_field) */
} shape_field;

static double table_field(void *ctx, vec3 d)
{
    const shape_field *f = ctx;
    double elevation = asin(clamp_cosine(d.z));
    const sky_grid *g = elevation > f->job->ms->grid.horizon_elevation ? f->above : &f->job->ss;
    return sky_grid_lookup_channel(g, elevation, render_relative_azimuth(f->job->sky, atan2(d.x, d.y)), f->channel);
}

/* Work item: the shape (next_order_shape.h) of one sky node of a table part, into shape. */
static void part_shapes(void *ctx, int64_t begin, int64_t end, int thread)
{
    const shape_field *field = ctx;
    const render_job *job = field->job;
    const fm_sky *sky = job->sky;
    (void)thread;
    for (int64_t i = begin; i < end; i++) {
        double e, phi;
        sky_grid_node_angles(&job->ms->grid, (int)i, &e, &phi);
        job->ms->shape[i] = next_order_shape_with(&sky->atm, sky->observer, render_view_direction(sky, e, phi),
                                                 sky->sun_dir, sky->atm.grid.count / 2, table_field, (void *)field,
                                                 field->sun_field);
    }
}

/* Fits one part of the table (order 2, or the orders above it) through its shape: that of the
 * field `above` scattered once more. */
static fm_status fit_part(render_job *job, sky_grid *part, const sky_grid *above, double sun_elevation, const double *y,
                          const double *var)
{
    const int K = job->sky->atm.grid.count;
    double sun_field[NEXT_ORDER_SUN_POINTS];
    shape_field field = {job, above, job->channels == 3 ? 1 : (job->channels == K ? K / 2 : 0), sun_field};
    next_order_sun_field(job->sky->sun_dir, table_field, &field, sun_field);
    fm_status s = parallel_for(job->params->threads, job->ms->grid.rows_sky * job->ms->grid.cols, 4, part_shapes,
                               &field, job->params->cancel, NULL);
    return s ? s : sky_grid_fit(part, sun_elevation, y, var, job->ms->shape, NULL);
}

/* The table's noise averaged over many nodes where a smooth fit is expected to be closer to the
 * truth than the nodes themselves (sky_grid_fit.h).  Parted, each part is fitted divided by its
 * shape, which holds the aerosols' aureole (order 2's), so that the fit keeps few cosines for
 * either: docs/decisions/2026-12-06-fit-by-order.md.  In deep twilight the table is fitted whole,
 * its nodes divided by their own shapes; at twilight the colour then goes through its ratios. */
fm_status ms_table_fit(render_job *job, double sun_elevation)
{
    ms_table *t = job->ms;
    fm_status s;
    if (t->orders) {
        if ((s = fit_part(job, &t->grid, &job->ss, sun_elevation, t->y, t->var)) ||
            (s = fit_part(job, &t->later, &t->grid, sun_elevation, t->later_y, t->later_var)))
            return s;
        for (size_t i = 0; i < (size_t)sky_grid_nodes(&t->grid) * (size_t)job->channels; i++)
            t->grid.values[i] += t->later.values[i];
    } else if ((s = sky_grid_fit(&t->grid, sun_elevation, t->y, t->var, t->shape, NULL))) {
        return s;
    }
    return t->ratio[0] ? sky_grid_fit_chroma(&t->grid, sun_elevation, (const double *const *)t->ratio,
                                             (const double *const *)t->ratio_var)
                       : FM_OK;
}

/* The live sky: the fast path's tables over a grid of sun elevations, built once per atmosphere;
 * a map per sun from the four nearest elevations' tables (live.h, docs/rendering.md "Live sky"). */
#include "render/live.h"

#include "base/hash.h"
#include "base/param_range.h"
#include "base/platform.h"
#include "base/status.h"
#include "base/text.h"
#include "base/units.h"
#include "render/aureole_fill.h"
#include "render/fog_table.h"
#include "render/live_smooth.h"
#include "render/ms_table.h"
#include "render/render.h"
#include "transport/shadow_flight_build.h"
#include "transport/sky_grid_refine.h"
#include "transport/twilight.h"
#include "sky.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The sun elevations of the tables (degrees): 1 degree apart where the sun's light through the
 * horizon changes fastest, wider by day and in deep twilight, where the sky's logarithm changes
 * smoothly; no more than 7.5 apart at the top, where the single-scattering table's bright band
 * around the sun moves with it (docs/decisions/2026-12-06-live-sky.md). */
static const double SUN_DEG[] = {-20, -17.5, -15, -12.5, -10, -8, -6, -4.5, -3, -2, -1, 0, 1,
                                 2,   3.5,   5.5, 8,     11,  15, 20, 27,   35, 45, 52.5, 60, 67.5, 75, 82.5, 90};
#define NODES ((int)(sizeof SUN_DEG / sizeof SUN_DEG[0]))
#define QUALITY FM_QUALITY_PREVIEW
#define SAMPLE_SCALE 1.0
/* Below the horizon the paths cost several times a day's (twilight sampling): deep twilight's nodes
 * take a quarter of them, whose noise the smoothing across the sun elevation averages (live_smooth.h;
 * the same decision record).  The nodes above it (-4.5 to -1) are not smoothed, and their table's
 * level over the sky (and the ground's light, from the same paths) keeps all its noise: they take the
 * preview's paths (docs/decisions/2026-12-07-live-twilight-bias.md). */
#define DEEP_TWILIGHT_PATH_SCALE 0.25
/* Of those, the lowest nodes take more: their paths cost most and their tables are the noisiest, and
 * their noise is most of the hazy maps' error from -20 to -10 (as built, before any round of
 * refinement); the deep split's saving (docs/decisions/2026-12-07-deep-split-in-haze.md) pays for
 * it (docs/decisions/2026-12-07-live-as-built.md). */
static double deep_path_share(double sun_elevation_deg)
{
    return sun_elevation_deg < -16.0 ? 2.0 : sun_elevation_deg < -9.0 ? 1.25 : 1.0;
}
/* Each node draws its own paths (its index seeds them), so that a map between two nodes averages two
 * noises, not one noise twice; in twilight above deep twilight one seed for all gave every node one
 * realisation of its table's level (docs/decisions/2026-12-07-live-twilight-bias.md).  By day the
 * nodes from SMOOTH_FROM_DEG up have their multiple-scattering tables smoothed across the sun
 * elevation (live_smooth.h); below, the sky changes too fast with the sun for the smoothing
 * (docs/decisions/2026-12-06-live-day-nodes.md).  Deep twilight's tables are smoothed across the sun
 * elevation among themselves (live_smooth_deep_twilight; docs/decisions/2026-12-06-live-twilight.md). */
#define SMOOTH_FROM_DEG 3.5
/* From HIGH_SUN_DEG up the sky's multiple scattering is a smaller part of it and changes slowest
 * with the sun: half the paths, whose noise the smoothing takes back (the same decision record). */
#define HIGH_SUN_DEG 13.0
#define HIGH_SUN_PATH_SCALE 0.5
/* Maps (and the nodes' ground irradiance) read the multiple-scattering table through a cubic between
 * its nodes (sky_grid_refine.h): the preview's coarse table read bilinearly made deep twilight's
 * clear sky about 1 % bright (docs/decisions/2026-12-08-live-deep-bright.md).  Fog's finer table
 * (fog_table_size) is read as it is. */
#define MS_REFINE 8
static int ms_refine(const fm_sky_live *live) { return fog_table_sky(live->sky) ? 1 : MS_REFINE; }

fm_status live_sky_params(const fm_sky_params *params, fm_sky_params *out, fm_error *err)
{
    fm_sky_params p = *params;
    if (p.earth_sun_distance_au == FM_SUN_FROM_TIME) { /* the date's (with or without a time), or 1 AU */
        fm_solar_position solar;
        unsigned computed;
        int has_solar;
        fm_status s = sky_resolve_sun(params, &p, &solar, &computed, &has_solar, err);
        if (s)
            return s;
    }
    p.hour = FM_NO_TIME; /* and without a time the clock's fields shape nothing in the tables */
    p.utc_offset_min = 0;
    p.delta_t_s = FM_DELTA_T_ESTIMATE;
    p.sun_elevation_deg = 45.0;
    p.sun_azimuth_deg = 180.0;
    *out = p;
    return FM_OK;
}

static int band_nodes(const fm_sky_live *live);

/* Copies of the caller's strings (names, paths) in place of them: the live sky outlives the request
 * that made it (serve's cache), and its sky, its later builds and its saved key read them. */
static int own_strings(fm_sky_live *live)
{
    fm_sky_params *p = &live->params;
    const char **field[LIVE_STRINGS] = {&p->biome, &p->clouds, &p->atmosphere_file, &p->presets_dir, &p->cache_dir};
    for (int i = 0; i < LIVE_STRINGS; i++) {
        if (!*field[i])
            continue;
        if (!(live->strings[i] = text_copy(*field[i])))
            return -1;
        *field[i] = live->strings[i];
    }
    return 0;
}

fm_status live_alloc(const fm_sky_params *params, fm_sky_live **out, fm_error *err)
{
    *out = NULL;
    fm_sky_live *live = calloc(1, sizeof *live);
    if (!live || pthread_mutex_init(&live->lock, NULL)) {
        free(live);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    }
    atomic_init(&live->band_pending, 0);
    fm_sky_live_key(params, live->key);
    fm_status s = live_sky_params(params, &live->params, err);
    if (!s && own_strings(live))
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    if (!s)
        s = fm_sky_create(&live->params, &live->sky, err);
    if (!s && !(live->nodes = calloc(NODES, sizeof *live->nodes)))
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    if (s) {
        fm_sky_live_destroy(live);
        return s;
    }
    const fm_sky *sky = live->sky;
    live->quality = QUALITY;
    live->sample_scale = SAMPLE_SCALE;
    live->q = render_quality_settings(QUALITY, SAMPLE_SCALE);
    live->channels = sky->atm.grid.colour ? 3 : 1;
    live->count = NODES;
    /* in fog the column's nodes fill the finer table that the forward light about the sun wants
     * (fog_table_size); the nodes of paths (twilight) keep theirs, resampled into it (node_end) */
    quality_settings q = live->q;
    if (fog_table_sky(sky))
        fog_table_size(&q);
    const double horizon = asin(horizon_mu(&sky->atm, v3_length(sky->observer)));
    for (int i = 0; i < NODES && !s; i++) {
        live_node *n = &live->nodes[i];
        n->sun_elevation_deg = SUN_DEG[i];
        if (sky_grid_init(&n->ss, horizon, q.ss_rows_sky, q.ss_rows_ground, q.ss_cols, live->channels, 1) ||
            sky_grid_init(&n->ms, horizon, q.ms_rows_sky, q.ms_rows_ground, q.ms_cols, live->channels, 0) ||
            aureole_init(&n->aureole, live->channels))
            s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the live sky's tables");
    }
    /* the twilight band's raw tables as its nodes' jobs make them (live->q's size: twilight takes
     * paths); above deep twilight they keep their orders apart (ms_table.h), as the jobs' do */
    const int band = s ? 0 : band_nodes(live);
    if (!s && band && !(live->raw = calloc((size_t)band, sizeof *live->raw)))
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    for (int k = 0; k < band && !s; k++, live->raw_count++)
        if (ms_table_init(&live->raw[k], &live->q, horizon, live->channels, sky->atm.grid.count,
                          !twilight_deep(SUN_DEG[k]), live->channels == 3))
            s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the live sky's tables");
    if (s) {
        fm_sky_live_destroy(live);
        return s;
    }
    *out = live;
    return FM_OK;
}

/* A copy of the live sky's fm_sky with the sun at (elevation, azimuth): the tables are shared,
 * read-only (sky_sun.c); free() it. */
static fm_status sky_with_sun(const fm_sky_live *live, double elevation_deg, double azimuth_deg, fm_sky **out,
                              fm_error *err)
{
    fm_sky *sky = *out = malloc(sizeof *sky);
    if (!sky)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    *sky = *live->sky;
    fm_status s = fm_sky_set_sun(sky, elevation_deg, azimuth_deg, err);
    if (s) {
        free(sky);
        *out = NULL;
    }
    return s;
}

/* Whether maps read the node's aureole: interpolate_tables reads it for suns up to the node two
 * above it, and a map reads the grid only with the sun not far below the horizon (aureole_seen); in
 * deep twilight its rays are not traced (its grid keeps what it held, never read). */
static int aureole_read(const fm_sky_live *live, const live_node *node, double horizon)
{
    int k = (int)(node - live->nodes);
    return k + 2 >= live->count || aureole_seen(live->nodes[k + 2].sun_elevation_deg * FM_DEG, horizon);
}

/* One node's tables in the making: its sky (the sun at the node's elevation), the fast path's job
 * and what the job points to (build_node). */
typedef struct node_build {
    live_node *node;
    fm_sky *sky;
    fm_render_params rp;
    ms_table ms;
    render_job job;
    twilight_sampling *twilight;
} node_build;

/* The node's job up to its multiple-scattering paths (render_fast_tables_begin); in deep twilight
 * its guided flights' light from the columns shared by every node (shadow_flight_build.h).  b stays
 * where it is until node_build_free (the job points into it). */
static fm_status node_begin(const fm_sky_live *live, live_node *node, const shadow_flight_columns *flights,
                            int refine_round, const atomic_int *cancel, node_build *b, fm_error *err)
{
    memset(b, 0, sizeof *b);
    b->node = node;
    fm_status s = sky_with_sun(live, node->sun_elevation_deg, 180.0, &b->sky, err);
    if (s)
        return s;
    b->rp = fm_render_params_default();
    b->rp.quality = live->quality;
    b->rp.sample_scale = live->sample_scale;
    b->rp.threads = live->params.threads;
    b->rp.cancel = cancel;
    render_job *job = &b->job;
    job->sky = b->sky;
    job->params = &b->rp;
    job->ms = &b->ms;
    job->channels = live->channels;
    job->fine_fog_table = 1;
    job->shared_flights = flights;
    job->ms_refine = ms_refine(live);
    job->q = live->q;
    if (node->sun_elevation_deg >= HIGH_SUN_DEG)
        job->q.ms_paths = (int)fmax(1.0, round(job->q.ms_paths * HIGH_SUN_PATH_SCALE));
    if (twilight_deep(node->sun_elevation_deg)) {
        const double share = DEEP_TWILIGHT_PATH_SCALE * deep_path_share(node->sun_elevation_deg);
        job->q.ms_paths = (int)fmax(1.0, round(job->q.ms_paths * share));
        job->q.ground_paths = (int)fmax(1.0, round(job->q.ground_paths * DEEP_TWILIGHT_PATH_SCALE));
    }
    const uint64_t moved = LIVE_SEED_STRIDE * live->seed + ((uint64_t)refine_round << LIVE_ROUND_SEED_SHIFT);
    job->seed = mix64((uint64_t)(node - live->nodes) + 1 + moved);
    if (!(s = render_twilight(job, &b->twilight, err))) {
        job->twilight = b->twilight;
        s = render_fast_tables_begin(job, err);
    }
    return s;
}

/* The job's multiple-scattering table into the node's: copied where they have the same size, else
 * (a table of paths in fog, whose nodes take the column's finer one) read at the node's directions. */
static void table_into_node(const sky_grid *from, sky_grid *to)
{
    if (from->rows_sky == to->rows_sky && from->rows_ground == to->rows_ground && from->cols == to->cols) {
        memcpy(to->values, from->values, sizeof(float) * (size_t)sky_grid_nodes(to) * (size_t)to->channels);
        return;
    }
    for (int i = 0; i < sky_grid_nodes(to); i++) {
        double elevation, azimuth;
        sky_grid_node_angles(to, i, &elevation, &azimuth);
        sky_grid_lookup(from, elevation, azimuth, &to->values[(size_t)i * (size_t)to->channels]);
    }
}

/* The node's job after its multiple-scattering paths: the rest of its tables, its aureole, and
 * the tables into the node. */
static fm_status node_end(const fm_sky_live *live, node_build *b, fm_error *err)
{
    live_node *node = b->node;
    render_job *job = &b->job;
    fm_status s = render_fast_tables_end(job, node->sun_elevation_deg * FM_DEG, err);
    if (!s && aureole_read(live, node, job->ss.horizon_elevation) &&
        (s = aureole_fill(&node->aureole, job, asin(clamp_cosine(b->sky->sun_dir.z)))))
        s = s == FM_ERR_CANCELLED ? s : fm_fail(err, s, "the live sky's aureole: %s", fm_status_name(s));
    if (!s) {
        memcpy(node->ss.values, job->ss.values, sizeof(float) * (size_t)sky_grid_nodes(&node->ss) * live->channels);
        table_into_node(&b->ms.grid, &node->ms);
        node->paths_per_node = job->paths_per_node;
    }
    return s;
}

static void node_build_free(node_build *b)
{
    free(b->twilight);
    render_tables_free(&b->job);
    free(b->sky);
    b->twilight = NULL;
    b->sky = NULL;
}

/* Whether the job's multiple-scattering table is of paths the size and kind (parted or not) of the
 * raw table's (not the fog's column): what a round of refinement can add to. */
static int raw_fits(const ms_table *raw, const node_build *b)
{
    return !fog_table_applies(&b->job) && !b->ms.orders == !raw->orders &&
           sky_grid_nodes(&b->ms.grid) == sky_grid_nodes(&raw->grid);
}

/* A band node's raw table becomes its job's (the job then frees the one it replaces); 0 paths when
 * the job's is not of paths. */
static void keep_raw(fm_sky_live *live, node_build *b)
{
    const int k = (int)(b->node - live->nodes);
    if (k >= live->raw_count)
        return;
    if (!raw_fits(&live->raw[k], b)) {
        live->raw[k].paths = 0;
        return;
    }
    ms_table t = live->raw[k];
    live->raw[k] = b->ms;
    b->ms = t;
}

/* The tables of one node: the fast path's, for a sun at the node's elevation. */
static fm_status build_node(fm_sky_live *live, live_node *node, const shadow_flight_columns *flights,
                            const atomic_int *cancel, fm_error *err)
{
    node_build b;
    fm_status s = node_begin(live, node, flights, 0, cancel, &b, err);
    if (!s && !(s = render_fast_tables_fill(&b.job, node->sun_elevation_deg * FM_DEG, err)))
        s = node_end(live, &b, err);
    if (!s)
        keep_raw(live, &b);
    node_build_free(&b);
    return s;
}

/* The day nodes SHARED_WALK_STRIDE apart (by index) from SHARED_FROM_DEG up trace their
 * multiple-scattering walks once for all their suns (ms_table_fill_shared): the walk from the
 * observer does not depend on the sun by day, and in sun-relative coordinates neither does a
 * table's view direction.  A map reads four nodes' tables, each smoothed over five nodes
 * (live_smooth.h): eight nodes apart, no map reads two tables with the same walks.  The group takes
 * the paths of its node below HIGH_SUN_DEG, and shares only when it has one: the sun guide's share
 * is split among the suns, which costs a high sun's table about half its paths' worth, so high
 * nodes gain from the walks of a node with twice their paths, and a group of high nodes alone would
 * gain nothing (docs/decisions/2026-12-06-live-shared-walks.md). */
#define SHARED_FROM_DEG 0.0
#define SHARED_WALK_STRIDE 8

/* The nodes of one group (group[0..count-1], their builds begun): the shareable ones filled
 * together when one of them draws more paths than the others, and it is the one with the rising
 * segments' estimator if any has it (its walks' first: ms_table_fill_shared), the rest alone; then
 * all finished (docs/decisions/2026-12-07-live-day-speed.md). */
static fm_status fill_group(const fm_sky_live *live, node_build *group, int count, fm_error *err)
{
    render_job *jobs[PATH_SUNS_MAX];
    int shareable = 0, most = 0, fewer = 0, rising = 0;
    fm_status s = FM_OK;
    for (int j = 0; j < count; j++)
        if (render_fast_tables_shareable(&group[j].job)) {
            jobs[shareable++] = &group[j].job;
            most = most > group[j].job.q.ms_paths ? most : group[j].job.q.ms_paths;
        }
    for (int j = 0; j < shareable; j++) {
        fewer += jobs[j]->q.ms_paths < most;
        if (ms_table_walk_rising(jobs[j]) && rising++ == 0) { /* the first of the walks' tables */
            render_job *t = jobs[0];
            jobs[0] = jobs[j];
            jobs[j] = t;
        }
    }
    const int share = fewer > 0 && fewer + 1 == shareable && rising <= 1 && jobs[0]->q.ms_paths == most;
    for (int j = 0; j < count && !s; j++)
        if (!share || !render_fast_tables_shareable(&group[j].job))
            s = render_fast_tables_fill(&group[j].job, group[j].node->sun_elevation_deg * FM_DEG, err);
    if (share && !s) {
        for (int j = 0; j < shareable; j++) {
            jobs[j]->q.ms_paths = most;
            jobs[j]->seed = jobs[0]->seed;
        }
        s = render_fast_tables_fill_shared(jobs, shareable, err);
    }
    for (int j = 0; j < count && !s; j++)
        s = node_end(live, &group[j], err);
    return s;
}

/* The day nodes from from_deg to to_deg (SHARED_FROM_DEG up) by groups of shared walks; fresh[i]
 * set for each node built. */
static fm_status build_shared_nodes(fm_sky_live *live, double from_deg, double to_deg, const atomic_int *cancel,
                                    unsigned char *fresh, fm_error *err)
{
    fm_status s = FM_OK;
    for (int g = 0; g < SHARED_WALK_STRIDE && !s; g++) {
        node_build group[PATH_SUNS_MAX];
        int count = 0;
        for (int i = g; i < live->count && !s; i += SHARED_WALK_STRIDE) {
            const double e = live->nodes[i].sun_elevation_deg;
            if (e < SHARED_FROM_DEG || e < from_deg || e > to_deg)
                continue;
            assert(count < PATH_SUNS_MAX);
            s = node_begin(live, &live->nodes[i], NULL, 0, cancel, &group[count++], err);
        }
        if (!s && count)
            s = fill_group(live, group, count, err);
        for (int j = 0; j < count; j++) {
            fresh[group[j].node - live->nodes] = !s;
            node_build_free(&group[j]);
        }
    }
    return s;
}

/* The guided flights' light (shadow_flight_build.h) for the deep twilight nodes from from_deg to
 * to_deg, once: from the lowest one's local sun elevation to the highest one's table's last column
 * (c->value NULL when there is none). */
static fm_status shared_flights(const fm_sky_live *live, double from_deg, double to_deg, const atomic_int *cancel,
                                shadow_flight_columns *c, fm_error *err)
{
    double lo = INFINITY, hi = -INFINITY;
    *c = (shadow_flight_columns){0};
    for (int i = 0; i < live->count; i++) {
        double e = live->nodes[i].sun_elevation_deg;
        if (e >= from_deg && e <= to_deg && twilight_deep(e)) {
            lo = fmin(lo, e);
            hi = fmax(hi, e);
        }
    }
    if (!(lo <= hi))
        return FM_OK;
    fm_sky *sky = NULL;
    fm_status built = sky_with_sun(live, lo, 180.0, &sky, err);
    if (built)
        return built;
    path_context single = sky_path_context(sky, 1, 1);
    double up_to = (hi + (SHADOW_FLIGHT_SUNS - 1)) * FM_DEG;
    fm_status s = shadow_flight_columns_build(c, &single, sky->observer, up_to, SHADOW_FLIGHT_COLUMN_STEP,
                                              live->params.threads, cancel);
    free(sky);
    return s && s != FM_ERR_CANCELLED ? fm_fail(err, s, "the twilight guide: %s", fm_status_name(s)) : s;
}

/* The deep twilight smoothing (live_smooth_deep_twilight) after a build that made deep nodes: the
 * fresh nodes and those built before outside deep twilight take part (the band built on first use
 * reads the twilight nodes built with the day, as a whole build does); nothing when no deep node is
 * fresh.  Returns nonzero when out of memory. */
static int smooth_deep_twilight(fm_sky_live *live, const unsigned char *fresh)
{
    int deep = 0;
    for (int i = 0; i < live->count; i++)
        deep |= fresh[i] && twilight_deep(live->nodes[i].sun_elevation_deg);
    unsigned char *part = deep ? malloc((size_t)live->count) : NULL;
    for (int i = 0; part && i < live->count; i++)
        part[i] = fresh[i] || (live->nodes[i].built && !twilight_deep(live->nodes[i].sun_elevation_deg));
    int failed = deep && (!part || live_smooth_deep_twilight(live, part) != FM_OK);
    free(part);
    return failed;
}

fm_status live_build_nodes(fm_sky_live *live, double from_deg, double to_deg, const atomic_int *cancel,
                           fm_error *err)
{
    unsigned char *fresh = calloc((size_t)live->count, 1);
    if (!fresh)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    for (int i = 0; i < live->count; i++) /* until built whole: a failure leaves raw tables */
        if (live->nodes[i].sun_elevation_deg >= from_deg && live->nodes[i].sun_elevation_deg <= to_deg)
            live->nodes[i].built = 0;
    shadow_flight_columns flights;
    fm_status s = shared_flights(live, from_deg, to_deg, cancel, &flights, err);
    for (int i = 0; i < live->count && !s; i++)
        if (live->nodes[i].sun_elevation_deg >= from_deg && live->nodes[i].sun_elevation_deg <= to_deg &&
            live->nodes[i].sun_elevation_deg < SHARED_FROM_DEG) {
            s = build_node(live, &live->nodes[i], &flights, cancel, err);
            fresh[i] = !s;
        }
    shadow_flight_columns_free(&flights);
    if (!s)
        s = build_shared_nodes(live, from_deg, to_deg, cancel, fresh, err);
    /* in fog the day nodes' tables are the column's, without noise (fog_table.h) */
    const int smooth_day = !fog_table_sky(live->sky);
    if (!s && ((smooth_day && live_smooth_day(live, fresh, SMOOTH_FROM_DEG)) || smooth_deep_twilight(live, fresh)))
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the live sky's tables");
    for (int i = 0; i < live->count && !s; i++) {
        live->nodes[i].built |= fresh[i];
        if (fresh[i] && i < live->raw_count)
            live->rounds = 0; /* a band built anew holds no rounds */
    }
    free(fresh);
    return s == FM_ERR_CANCELLED ? fm_fail(err, s, "live sky cancelled") : s;
}

/* The twilight band: the nodes with the sun below the horizon, the lowest of the grid (0 to
 * band_nodes - 1): deep twilight's and the four above it.  It costs half the build, and maps read it
 * only for suns below the second node above it (1 degree: interpolate_tables reads a node below the
 * sun's interval), so fm_sky_live_create leaves it for the first map that reads it
 * (docs/decisions/2026-12-07-live-deep-band-on-first-use.md, 2026-12-07-live-twilight-bias.md); its
 * nodes' paths are what rounds of refinement add to (2026-12-07-live-twilight-refine.md).  Its nodes'
 * seeds, its shared flight columns and its smoothing are a whole build's; it writes none of the other
 * nodes. */
static int in_band(double sun_elevation_deg) { return sun_elevation_deg < 0.0; }

/* The number of nodes from the grid's lowest up for which in(elevation) holds. */
static int lowest_nodes(const fm_sky_live *live, int (*in)(double sun_elevation_deg))
{
    int n = 0;
    while (n < live->count && in(live->nodes[n].sun_elevation_deg))
        n++;
    return n;
}

static int band_nodes(const fm_sky_live *live) { return lowest_nodes(live, in_band); }

void live_settle_pending(fm_sky_live *live)
{
    const int deep = band_nodes(live);
    int others = 1, band = 1;
    for (int i = 0; i < live->count; i++)
        *(i < deep ? &band : &others) &= live->nodes[i].built;
    atomic_store(&live->band_pending, others && !band);
}

fm_status fm_sky_live_create(const fm_sky_params *params, const atomic_int *cancel, fm_sky_live **out,
                             fm_error *err)
{
    fm_sky_live *live;
    fm_status s = live_alloc(params, &live, err);
    if (s)
        return s;
    const int deep = band_nodes(live);
    const double from_deg = deep < live->count ? live->nodes[deep].sun_elevation_deg : 90.0;
    if ((s = live_build_nodes(live, from_deg, 90.0, cancel, err))) {
        fm_sky_live_destroy(live);
        return s;
    }
    live_settle_pending(live);
    *out = live;
    return FM_OK;
}

/* Where a sun elevation lies on the grid: between nodes i and i + 1 at t in [0, 1], and the nodes'
 * elevations x[0..3] (i - 1 to i + 2; lo, hi: whether i - 1 and i + 2 exist). */
typedef struct grid_place {
    int i, lo, hi;
    double t, x[4];
} grid_place;

static grid_place place_on_grid(const fm_sky_live *live, double elevation_deg)
{
    grid_place g = {0};
    while (g.i + 2 < live->count && live->nodes[g.i + 1].sun_elevation_deg <= elevation_deg)
        g.i++;
    g.lo = g.i > 0;
    g.hi = g.i + 2 < live->count;
    for (int k = 0; k < 4; k++) {
        int n = g.i - 1 + k;
        g.x[k] = n >= 0 && n < live->count ? live->nodes[n].sun_elevation_deg : 0.0;
    }
    g.t = (elevation_deg - g.x[1]) / (g.x[2] - g.x[1]);
    return g;
}

/* The slope at a node from its neighbours' values (ym at hm before, yp at hp after) so that the
 * curve never overshoots its nodes: 0 at a local extremum, else the weighted harmonic mean of the
 * two secants (Fritsch & Butland, SIAM J. Sci. Stat. Comput. 5 (1984) 300), which leans to the
 * smaller one.  Where the sky's logarithm bends fast, as the zenith's single scattering as the sun
 * sinks toward -10 degrees (its scattering heights leave the air), an arithmetic mean of the secants
 * takes too much of the steep side and overshoots between the nodes. */
static double limited_slope(double ym, double y, double yp, double hm, double hp)
{
    double sm = (y - ym) / hm, sp = (yp - y) / hp;
    if (sm * sp <= 0.0)
        return 0.0;
    double wm = 2.0 * hp + hm, wp = hp + 2.0 * hm;
    return (wm + wp) / (wm / sm + wp / sp);
}

/* The slope at an end node (value y0) from the parabola through it and the next two nodes (y1 h1
 * after it, y2 h2 after that), with the sign of the first secant and at most three times it, so
 * that the curve never overshoots its nodes (Fritsch & Carlson, SIAM J. Numer. Anal. 17 (1980) 238).
 * The secant alone is the slope at the interval's middle: where the sky's logarithm bends (deep
 * twilight's level bends by -0.08 over 2.5 degrees at -17.5 in haze) the curve from the grid's lowest
 * node then lies 0.6 % below it (docs/decisions/2026-12-08-live-deep-interp.md). */
static double end_slope(double y0, double y1, double y2, double h1, double h2)
{
    const double s1 = (y1 - y0) / h1, s2 = (y2 - y1) / h2;
    const double d = ((2.0 * h1 + h2) * s1 - h1 * s2) / (h1 + h2);
    if (d * s1 <= 0.0)
        return 0.0;
    return fabs(d) > 3.0 * fabs(s1) ? 3.0 * s1 : d;
}

/* The monotone cubic Hermite interpolant through y[0..3] (at the nodes of g) at g's place; the
 * grid's lowest node takes end_slope, any other node without an outer neighbour (the grid's top,
 * where the sun passes the zenith; one beside an unlit value) its secant. */
static double hermite(const grid_place *g, const double y[4])
{
    const double h = g->x[2] - g->x[1], s = (y[2] - y[1]) / h, t = g->t;
    double d1 = g->lo                ? limited_slope(y[0], y[1], y[2], g->x[1] - g->x[0], h)
                : g->i == 0 && g->hi ? end_slope(y[1], y[2], y[3], h, g->x[3] - g->x[2])
                                     : s;
    double d2 = g->hi ? limited_slope(y[1], y[2], y[3], h, g->x[3] - g->x[2]) : s;
    double t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * y[1] + (t3 - 2 * t2 + t) * h * d1 + (3 * t2 - 2 * t3) * y[2] + (t3 - t2) * h * d2;
}

/* One value on the monotone cubic through the four nodes' values v[0..3] (of g): in their
 * logarithms where the interval's two values are positive, else in the values (light that one
 * node's sun does not reach, 0 there, as a shadowed direction in deep twilight, or a fit's dip to
 * 0).  An outer value that is not positive counts as absent in the logarithms, so that the slope at
 * a node, and the curve, depend on that node's two intervals alone and meet smoothly there. */
static double interpolate_value(const grid_place *g, const double v[4])
{
    if (!(v[1] > 0.0 && v[2] > 0.0))
        return hermite(g, v);
    grid_place h = *g;
    h.lo = g->lo && v[0] > 0.0;
    h.hi = g->hi && v[3] > 0.0;
    const double y[4] = {h.lo ? log(v[0]) : 0.0, log(v[1]), log(v[2]), h.hi ? log(v[3]) : 0.0};
    return exp(hermite(&h, y));
}

/* n values stored as logarithms (log(max(v, FM_GRID_FLOOR))) at the four nodes of g, interpolated
 * (interpolate_value) into out, also as logarithms. */
static void interpolate_logs(const grid_place *g, const float *const logs[4], size_t n, float *out)
{
    const double floor_log = log(FM_GRID_FLOOR) + 1.0; /* at or below: a 0 stored as the grid's floor */
    double v[4];
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 4; k++)
            v[k] = logs[k][i] > floor_log ? exp(logs[k][i]) : 0.0;
        double r = interpolate_value(g, v);
        out[i] = r > 0.0 ? logf((float)fmax(r, FM_GRID_FLOOR)) : logf(FM_GRID_FLOOR);
    }
}

/* The tables at g's sun elevation, into ss, ms and au (initialised like the nodes'), value by value
 * (interpolate_value).  The sky's brightness is neither linear nor exponential in the sun's
 * elevation (it follows the sine by day and falls by decades in twilight); a cubic in the logarithm
 * follows both. */
static void interpolate_tables(const fm_sky_live *live, const grid_place *g, sky_grid *ss, sky_grid *ms, aureole *au)
{
    const live_node *n[4];
    for (int k = 0; k < 4; k++)
        n[k] = &live->nodes[g->i - 1 + k < 0 ? 0 : (g->i - 1 + k >= live->count ? live->count - 1 : g->i - 1 + k)];
    const size_t nss = (size_t)sky_grid_nodes(ss) * live->channels, nms = (size_t)sky_grid_nodes(ms) * live->channels;
    const float *logs[4], *aureoles[4];
    for (int k = 0; k < 4; k++) {
        logs[k] = n[k]->ss.values;
        aureoles[k] = n[k]->aureole.values;
    }
    interpolate_logs(g, logs, nss, ss->values);
    interpolate_logs(g, aureoles, aureole_floats(au), au->values);
    double v[4];
    for (size_t i = 0; i < nms; i++) {
        for (int k = 0; k < 4; k++)
            v[k] = n[k]->ms.values[i];
        ms->values[i] = (float)interpolate_value(g, v);
    }
}

/* A sun below the grid (night): the fast path itself, at the tables' quality. */
static fm_status render_below_grid(const fm_sky *sky, const fm_render_params *rp, fm_image **out, fm_error *err)
{
    return fm_render(sky, rp, out, err);
}

/* Whether a map for a sun at elevation_deg reads a node of the band (only one not built when
 * `unbuilt`): one of the four nodes of its place on the grid (interpolate_tables); none below the
 * grid (render_below_grid).  With `unbuilt` the caller holds the lock. */
static int reads_band(const fm_sky_live *live, double elevation_deg, int unbuilt)
{
    if (!(elevation_deg >= live->nodes[0].sun_elevation_deg))
        return 0;
    const grid_place g = place_on_grid(live, elevation_deg);
    for (int k = g.i - 1; k <= g.i + 2; k++) {
        const live_node *n = &live->nodes[k < 0 ? 0 : (k >= live->count ? live->count - 1 : k)];
        if (in_band(n->sun_elevation_deg) && (!unbuilt || !n->built))
            return 1;
    }
    return 0;
}

int fm_sky_live_reads_refined(const fm_sky_live *live, double sun_elevation_deg)
{
    return reads_band(live, sun_elevation_deg, 0);
}

/* The twilight band when whole or a map at elevation_deg reads it and it is pending, once: a
 * thread that finds it building waits for it; a failed build leaves it pending. */
static fm_status build_band(fm_sky_live *live, int whole, double elevation_deg, const atomic_int *cancel, int *built,
                            fm_error *err)
{
    if (built)
        *built = 0;
    if (!atomic_load(&live->band_pending))
        return FM_OK;
    pthread_mutex_lock(&live->lock);
    fm_status s = FM_OK;
    const int deep = band_nodes(live);
    if (atomic_load(&live->band_pending) && deep > 0 && (whole || reads_band(live, elevation_deg, 1)) &&
        !(s = live_build_nodes(live, -90.0, live->nodes[deep - 1].sun_elevation_deg, cancel, err))) {
        atomic_store(&live->band_pending, 0);
        if (built)
            *built = 1;
    }
    pthread_mutex_unlock(&live->lock);
    return s;
}

fm_status fm_sky_live_prepare(fm_sky_live *live, double sun_elevation_deg, const atomic_int *cancel, int *built,
                              fm_error *err)
{
    return build_band(live, 0, sun_elevation_deg, cancel, built, err);
}

fm_status fm_sky_live_complete(fm_sky_live *live, const atomic_int *cancel, fm_error *err)
{
    return build_band(live, 1, 0.0, cancel, NULL, err);
}

int fm_sky_live_rounds(const fm_sky_live *live)
{
    return live->rounds;
}

int fm_sky_live_refinable(const fm_sky_live *live)
{
    if (atomic_load(&live->band_pending) || live->rounds >= LIVE_REFINE_ROUNDS || live->raw_count == 0)
        return 0;
    for (int k = 0; k < live->raw_count; k++)
        if (!live->nodes[k].built || live->raw[k].paths <= 0)
            return 0;
    return 1;
}

/* One band node's next round: its paths with the round's seeds, added to its raw table (the build's
 * and earlier rounds'; in twilight above deep twilight each order part to its own), the whole
 * fitted, and its single-scattering table remade (on the ground its diffuse light comes from the
 * whole table). The node's tables stay as they were. */
static fm_status refine_node(const fm_sky_live *live, int k, const shadow_flight_columns *flights, int pass,
                             const atomic_int *cancel, node_build *b, fm_error *err)
{
    live_node *node = &live->nodes[k];
    const double sun = node->sun_elevation_deg * FM_DEG;
    fm_status s = node_begin(live, node, flights, pass, cancel, b, err);
    if (!s && !(s = render_fast_tables_fill(&b->job, sun, err))) {
        if (!raw_fits(&live->raw[k], b))
            return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the live sky's twilight tables are not of paths");
        ms_table_add(&b->job, &live->raw[k]);
        s = render_fast_tables_end(&b->job, sun, err);
    }
    return s;
}

/* The round's tables into the band's nodes (its raw tables the rounds' sums), then the band smoothed
 * again; under the lock, so that a file saved meanwhile holds whole rounds. */
static fm_status refine_commit(fm_sky_live *live, node_build *b, int pass, fm_error *err)
{
    const int deep = live->raw_count;
    unsigned char *fresh = calloc((size_t)live->count, 1);
    if (!fresh)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    pthread_mutex_lock(&live->lock);
    for (int k = 0; k < deep; k++) {
        live_node *node = &live->nodes[k];
        memcpy(node->ss.values, b[k].job.ss.values,
               sizeof(float) * (size_t)sky_grid_nodes(&node->ss) * (size_t)live->channels);
        table_into_node(&b[k].ms.grid, &node->ms);
        node->paths_per_node = b[k].ms.paths;
        ms_table t = live->raw[k];
        live->raw[k] = b[k].ms;
        b[k].ms = t; /* freed with the round's jobs */
        fresh[k] = 1;
    }
    live->rounds = pass;
    const int failed = smooth_deep_twilight(live, fresh);
    pthread_mutex_unlock(&live->lock);
    free(fresh);
    return failed ? fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the live sky's tables") : FM_OK;
}

fm_status fm_sky_live_refine(fm_sky_live *live, const atomic_int *cancel, fm_error *err)
{
    if (!fm_sky_live_refinable(live))
        return FM_OK;
    const int deep = live->raw_count, pass = live->rounds + 1;
    node_build *b = deep > 0 ? calloc((size_t)deep, sizeof *b) : NULL;
    if (!b)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    shadow_flight_columns flights;
    fm_status s = shared_flights(live, -90.0, live->nodes[deep - 1].sun_elevation_deg, cancel, &flights, err);
    int begun = 0;
    for (; begun < deep && !s; begun++)
        s = refine_node(live, begun, &flights, pass, cancel, &b[begun], err);
    shadow_flight_columns_free(&flights);
    if (!s)
        s = refine_commit(live, b, pass, err);
    for (int k = 0; k < begun; k++)
        node_build_free(&b[k]);
    free(b);
    return s == FM_ERR_CANCELLED ? fm_fail(err, s, "live sky refinement cancelled") : s;
}

int fm_sky_live_is_complete(const fm_sky_live *live)
{
    return !atomic_load(&live->band_pending);
}

fm_status fm_sky_live_render(fm_sky_live *live, double sun_elevation_deg, double sun_azimuth_deg,
                             const fm_render_params *render, fm_image **out, fm_error *err)
{
    *out = NULL;
    if (render->spectral)
        return fm_fail_parameter(err, "spectral", "a live sky makes colour maps only");
    fm_status built = fm_sky_live_prepare(live, sun_elevation_deg, render->cancel, NULL, err);
    if (built)
        return built;
    fm_sky *sky = NULL;
    built = sky_with_sun(live, sun_elevation_deg, sun_azimuth_deg, &sky, err);
    if (built)
        return built;
    fm_render_params rp = *render;
    rp.quality = live->quality;
    rp.sample_scale = live->sample_scale;
    fm_status s;
    if (sun_elevation_deg < live->nodes[0].sun_elevation_deg) {
        s = render_below_grid(sky, &rp, out, err);
        free(sky);
        return s;
    }
    render_job job = {.sky = sky, .params = &rp};
    if ((s = render_start(&job, err))) {
        free(sky);
        return s;
    }
    job.q = live->q;
    render_quality_fit_footprint(&job.q, &job.cam, &rp);
    const grid_place g = place_on_grid(live, sun_elevation_deg);
    const live_node *a = &live->nodes[g.i], *b = &live->nodes[g.i + 1];
    sky_grid ms = {0}, fine = {0};
    aureole au = {0};
    if (sky_grid_init(&job.ss, a->ss.horizon_elevation, a->ss.rows_sky, a->ss.rows_ground, a->ss.cols,
                      live->channels, 1) ||
        sky_grid_init(&ms, a->ms.horizon_elevation, a->ms.rows_sky, a->ms.rows_ground, a->ms.cols, live->channels, 0) ||
        aureole_init(&au, live->channels))
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the live sky's tables");
    if (!s) {
        interpolate_tables(live, &g, &job.ss, &ms, &au);
        job.aureole = &au;
        job.aureole_frame = aureole_frame_of(asin(clamp_cosine(sky->sun_dir.z)));
        job.img->paths_per_node = g.t < 0.5 ? a->paths_per_node : b->paths_per_node;
        const int refine = ms_refine(live);
        if (refine > 1 && sky_grid_refine(&ms, refine, &fine))
            s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the live sky's tables");
        else
            s = render_fast_pixels(&job, refine > 1 ? &fine : &ms, err);
    }
    sky_grid_free(&job.ss);
    sky_grid_free(&ms);
    sky_grid_free(&fine);
    aureole_free(&au);
    s = render_finish(&job, s, out, err);
    free(sky);
    return s;
}

/* Adds a file's bytes to the key, when path names a readable file. */
static void hash_file(const char *path, uint64_t h[2])
{
    FILE *f = path ? platform_fopen(path, "rb") : NULL;
    if (!f)
        return;
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) {
        h[0] = hash_bytes(buf, n, h[0]);
        h[1] = hash_bytes(buf, n, h[1]);
    }
    fclose(f);
}

void fm_sky_live_key(const fm_sky_params *params, char out[33])
{
    fm_sky_params resolved = *params;
    if (live_sky_params(params, &resolved, NULL)) /* a bad date: its fields hash as they are */
        resolved = *params;
    const fm_sky_params *p = &resolved;
    char text[8192];
    /* every field that changes the tables; the date and place make the ozone profile (and column from
     * the climatology) and the day's Earth-Sun distance; no sun position, no time of day, no threads */
    int n = snprintf(text, sizeof text,
                     "live %d|alt %.17g|albedo %.17g|ozone %.17g|distance %.17g|wavelength %.17g|biome %s|"
                     "turbidity %.17g|aod %.17g|humidity %.17g|phase %d|atmosphere %s|presets %s",
                     LIVE_TABLE_VERSION, p->observer_altitude_m, p->ground_albedo, p->ozone_column_du,
                     p->earth_sun_distance_au, p->wavelength_nm, p->biome ? p->biome : "none", p->turbidity,
                     p->aod550, p->humidity_percent, (int)p->aerosol_phase,
                     p->atmosphere_file ? p->atmosphere_file : "", p->presets_dir ? p->presets_dir : "");
    /* clouds only when there are some, so that clear skies keep their keys */
    if ((p->clouds || p->fog_visibility_m > 0.0) && n > 0 && (size_t)n < sizeof text)
        n += snprintf(text + n, sizeof text - (size_t)n, "|clouds %s|tau %.17g|lwp %.17g|base %.17g|thick %.17g|fog %.17g",
                      p->clouds ? p->clouds : "", p->cloud_tau550, p->cloud_lwp_gm2, p->cloud_base_km,
                      p->cloud_thickness_km, p->fog_visibility_m);
    if (p->year != 0 && n > 0 && (size_t)n < sizeof text)
        snprintf(text + n, sizeof text - (size_t)n, "|date %d-%d-%d|place %.17g %.17g|utc %d|delta %.17g",
                 p->year, p->month, p->day, p->latitude_deg, p->longitude_deg, p->utc_offset_min, p->delta_t_s);
    uint64_t h[2] = {hash_bytes(text, strlen(text), 1), hash_bytes(text, strlen(text), 2)};
    hash_file(p->atmosphere_file, h);
    hash_file(p->biome, h); /* a biome given as a file; a name reads nothing */
    for (const char *c = p->clouds; c && *c;) { /* each cloud given as a file, alike */
        const char *end = strchr(c, ',');
        size_t len = end ? (size_t)(end - c) : strlen(c);
        char name[1024];
        if (len < sizeof name) {
            memcpy(name, c, len);
            name[len] = '\0';
            hash_file(name, h);
        }
        c = end ? end + 1 : c + len;
    }
    snprintf(out, 33, "%016llx%016llx", (unsigned long long)h[0], (unsigned long long)h[1]);
}

void fm_sky_live_destroy(fm_sky_live *live)
{
    if (!live)
        return;
    for (int i = 0; i < live->count && live->nodes; i++) {
        sky_grid_free(&live->nodes[i].ss);
        sky_grid_free(&live->nodes[i].ms);
        aureole_free(&live->nodes[i].aureole);
    }
    free(live->nodes);
    for (int k = 0; k < live->raw_count; k++)
        ms_table_free(&live->raw[k]);
    free(live->raw);
    fm_sky_destroy(live->sky);
    for (int i = 0; i < LIVE_STRINGS; i++)
        free(live->strings[i]);
    pthread_mutex_destroy(&live->lock);
    free(live);
}

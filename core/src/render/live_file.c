/* The live sky's file: a sealed file (base/sealed_file.h: magic, version, byte order, the
 * atmosphere's key, the tables' size and checksum) of the tables: their layout (nodes, channels,
 * quality, the grids' sizes), then per node its sun elevation, paths, whether it is built and the
 * three tables' values (single scattering, multiple scattering, the aureole; native floats; zeros for
 * a node not built yet: the twilight band before its first use, live.c); then the rounds of
 * refinement and the twilight band's raw tables (per node its paths, their sums at every grid
 * wavelength, their moments and shapes, and above deep twilight the sums and squares of orders 3 and
 * up: what the next round adds to; zeros before the band is built).  Checked before anything in it is used. */
#include "base/sealed_file.h"
#include "base/status.h"
#include "render/live.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FILE_VERSION 6u
#define CHECKSUM_SEED 0x6c697665ull /* "live" */

/* ---- the tables ------------------------------------------------------------------------------ */

typedef struct layout {
    int32_t count, channels, quality, dims[8];
    double sample_scale;
} layout;

static layout layout_of(const fm_sky_live *live)
{
    const sky_grid *ss = &live->nodes[0].ss, *ms = &live->nodes[0].ms;
    layout l;
    memset(&l, 0, sizeof l); /* the padding too: layouts are compared and hashed as bytes */
    l.count = live->count;
    l.channels = live->channels;
    l.quality = (int32_t)live->quality;
    const int32_t dims[8] = {ss->rows_sky, ss->rows_ground, ss->cols, ms->rows_sky, ms->rows_ground, ms->cols,
                             AUREOLE_ROWS, AUREOLE_COLS};
    memcpy(l.dims, dims, sizeof dims);
    l.sample_scale = live->sample_scale;
    return l;
}

static size_t table_floats(const fm_sky_live *live, const sky_grid *g)
{
    return (size_t)sky_grid_nodes(g) * (size_t)live->channels;
}

/* One raw table's doubles: per node its sums (K), shape and moments; parted, the later orders' sums
 * (K) and both parts' squares (2). */
static size_t raw_doubles(const fm_sky_live *live, const ms_table *t)
{
    const size_t K = (size_t)live->sky->atm.grid.count;
    const size_t per_node = K + 1 + sizeof(node_moments) / sizeof(double) + (t->orders ? K + 2 : 0);
    return (size_t)sky_grid_nodes(&t->grid) * per_node;
}


static size_t payload_size(const fm_sky_live *live)
{
    size_t n = sizeof(layout) + sizeof(int32_t);
    for (int k = 0; k < live->raw_count; k++)
        n += sizeof(int32_t) + sizeof(double) * raw_doubles(live, &live->raw[k]);
    for (int i = 0; i < live->count; i++)
        n += sizeof(double) + 2 * sizeof(int32_t) +
             sizeof(float) * (table_floats(live, &live->nodes[i].ss) + table_floats(live, &live->nodes[i].ms) +
                              aureole_floats(&live->nodes[i].aureole));
    return n;
}

/* n bytes of v, or zeros without v */
static unsigned char *put(unsigned char *out, const void *v, size_t n)
{
    if (v)
        memcpy(out, v, n);
    else
        memset(out, 0, n);
    return out + n;
}

static void payload_write(const fm_sky_live *live, unsigned char *out)
{
    layout l = layout_of(live);
    out = put(out, &l, sizeof l);
    for (int i = 0; i < live->count; i++) {
        const live_node *n = &live->nodes[i];
        int32_t paths = n->built ? n->paths_per_node : 0, built = n->built != 0;
        out = put(out, &n->sun_elevation_deg, sizeof(double));
        out = put(out, &paths, sizeof paths);
        out = put(out, &built, sizeof built);
        out = put(out, built ? n->ss.values : NULL, sizeof(float) * table_floats(live, &n->ss));
        out = put(out, built ? n->ms.values : NULL, sizeof(float) * table_floats(live, &n->ms));
        out = put(out, built ? n->aureole.values : NULL, sizeof(float) * aureole_floats(&n->aureole));
    }
    int32_t rounds = live->rounds;
    out = put(out, &rounds, sizeof rounds);
    for (int k = 0; k < live->raw_count; k++) {
        const ms_table *t = &live->raw[k];
        const int have = live->nodes[k].built && t->paths > 0;
        const int32_t paths = have ? t->paths : 0;
        const size_t nodes = (size_t)sky_grid_nodes(&t->grid), K = (size_t)live->sky->atm.grid.count;
        out = put(out, &paths, sizeof paths);
        out = put(out, have ? t->sum : NULL, sizeof(double) * nodes * K);
        out = put(out, have ? t->shape : NULL, sizeof(double) * nodes);
        out = put(out, have ? t->moments : NULL, sizeof(node_moments) * nodes);
        if (t->orders) {
            out = put(out, have ? t->later_sum : NULL, sizeof(double) * nodes * K);
            for (size_t i = 0; i < nodes; i++)
                out = put(out, have ? t->orders[i].yy : NULL, sizeof t->orders[i].yy);
        }
    }
}

static const unsigned char *get(const unsigned char *in, void *v, size_t n)
{
    memcpy(v, in, n);
    return in + n;
}

static int all_finite_doubles(const double *v, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (!isfinite(v[k]))
            return 0;
    return 1;
}

/* The rounds and the raw tables (after the nodes), or why they do not fit. */
static const char *raw_read(fm_sky_live *live, const unsigned char *in)
{
    int32_t rounds;
    in = get(in, &rounds, sizeof rounds);
    if (rounds < 0 || rounds > LIVE_REFINE_ROUNDS)
        return "another number of rounds";
    live->rounds = rounds;
    for (int k = 0; k < live->raw_count; k++) {
        ms_table *t = &live->raw[k];
        const size_t nodes = (size_t)sky_grid_nodes(&t->grid), K = (size_t)live->sky->atm.grid.count;
        int32_t paths;
        in = get(in, &paths, sizeof paths);
        /* a built band's raw tables hold its paths (those of every round), else none */
        if (paths < 0 || (paths > 0) != (live->nodes[k].built && live->nodes[k].paths_per_node == paths) ||
            (paths == 0 && rounds > 0))
            return "raw tables that are not the nodes'";
        t->paths = paths;
        in = get(in, t->sum, sizeof(double) * nodes * K);
        in = get(in, t->shape, sizeof(double) * nodes);
        in = get(in, t->moments, sizeof(node_moments) * nodes);
        if (!all_finite_doubles(t->sum, nodes * K) || !all_finite_doubles(t->shape, nodes) ||
            !all_finite_doubles((const double *)t->moments, nodes * sizeof(node_moments) / sizeof(double)))
            return "a value that is not a number";
        if (t->orders) {
            in = get(in, t->later_sum, sizeof(double) * nodes * K);
            for (size_t i = 0; i < nodes; i++) {
                in = get(in, t->orders[i].yy, sizeof t->orders[i].yy);
                if (!all_finite_doubles(t->orders[i].yy, 2))
                    return "a value that is not a number";
            }
            if (!all_finite_doubles(t->later_sum, nodes * K))
                return "a value that is not a number";
        }
    }
    return NULL;
}

static int all_finite(const float *v, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (!isfinite(v[k]))
            return 0;
    return 1;
}

/* The file's tables into live (allocated for this atmosphere by live_alloc), or why they do not fit. */
static const char *payload_read(fm_sky_live *live, const unsigned char *in, size_t bytes)
{
    layout want = layout_of(live), got;
    if (bytes != payload_size(live))
        return "tables of another size";
    in = get(in, &got, sizeof got);
    if (memcmp(&got, &want, sizeof got) != 0)
        return "tables of another layout";
    for (int i = 0; i < live->count; i++) {
        live_node *n = &live->nodes[i];
        double e;
        int32_t paths, built;
        in = get(in, &e, sizeof e);
        in = get(in, &paths, sizeof paths);
        in = get(in, &built, sizeof built);
        if (e != n->sun_elevation_deg || paths < 0 || (built != 0 && built != 1))
            return "tables of other sun elevations";
        n->paths_per_node = paths;
        n->built = built;
        in = get(in, n->ss.values, sizeof(float) * table_floats(live, &n->ss));
        in = get(in, n->ms.values, sizeof(float) * table_floats(live, &n->ms));
        in = get(in, n->aureole.values, sizeof(float) * aureole_floats(&n->aureole));
        if (!all_finite(n->ss.values, table_floats(live, &n->ss)) ||
            !all_finite(n->ms.values, table_floats(live, &n->ms)) ||
            !all_finite(n->aureole.values, aureole_floats(&n->aureole)))
            return "a value that is not a number";
    }
    const char *why = raw_read(live, in);
    if (why)
        return why;
    live_settle_pending(live);
    return NULL;
}

/* ---- the file -------------------------------------------------------------------------------- */

static const sealed_format LIVE_FORMAT = {{'F', 'M', 'L', 'I', 'V', 'E', '\r', '\n'}, FILE_VERSION, CHECKSUM_SEED,
                                          "live sky", "the tables of another atmosphere"};

fm_status fm_sky_live_save(const fm_sky_live *live, const char *path, fm_error *err)
{
    size_t n = payload_size(live);
    unsigned char *body = malloc(n);
    if (!body)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    /* not while a map's thread builds the twilight band (its tables half made): the lock is the
     * tables', not part of what the caller sees as the live sky, so a const one locks it too */
    pthread_mutex_t *lock = (pthread_mutex_t *)&live->lock;
    pthread_mutex_lock(lock);
    payload_write(live, body);
    pthread_mutex_unlock(lock);
    fm_status s = sealed_file_write(path, &LIVE_FORMAT, live->key, body, n, err);
    free(body);
    return s;
}

fm_status fm_sky_live_load(const fm_sky_params *params, const char *path, fm_sky_live **out, fm_error *err)
{
    *out = NULL;
    char key[33];
    fm_sky_live_key(params, key);
    unsigned char *body;
    size_t n;
    fm_status s = sealed_file_read(path, &LIVE_FORMAT, key, &body, &n, err);
    if (s)
        return s;
    fm_sky_live *live = NULL;
    const char *why = NULL;
    s = live_alloc(params, &live, err);
    if (!s && (why = payload_read(live, body, n)))
        s = fm_fail(err, FM_ERR_INVALID_ARGUMENT, "live sky '%s': %s", path, why);
    free(body);
    if (s) {
        fm_sky_live_destroy(live);
        return s;
    }
    *out = live;
    return FM_OK;
}

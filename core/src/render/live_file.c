/* The live sky's file: a header (magic, version, byte order, the atmosphere's key, the tables' size
 * and checksum) and the tables: their layout (nodes, channels, quality, the grids' sizes), then per
 * node its sun elevation, paths and the two tables' values (native floats; the byte order mark
 * refuses another machine's).  Written to a temporary file beside the path and renamed; read whole
 * and checked before anything in it is used. */
#include "base/hash.h"
#include "base/platform.h"
#include "base/status.h"
#include "render/live.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char MAGIC[8] = {'F', 'M', 'L', 'I', 'V', 'E', '\r', '\n'};
#define FILE_VERSION 1u
#define BYTE_ORDER_MARK 0x01020304u
#define CHECKSUM_SEED 0x6c697665ull /* "live" */

/* ---- the tables ------------------------------------------------------------------------------ */

typedef struct layout {
    int32_t count, channels, quality, dims[6];
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
    const int32_t dims[6] = {ss->rows_sky, ss->rows_ground, ss->cols, ms->rows_sky, ms->rows_ground, ms->cols};
    memcpy(l.dims, dims, sizeof dims);
    l.sample_scale = live->sample_scale;
    return l;
}

static size_t table_floats(const fm_sky_live *live, const sky_grid *g)
{
    return (size_t)sky_grid_nodes(g) * (size_t)live->channels;
}

static size_t payload_size(const fm_sky_live *live)
{
    size_t n = sizeof(layout);
    for (int i = 0; i < live->count; i++)
        n += sizeof(double) + sizeof(int32_t) +
             sizeof(float) * (table_floats(live, &live->nodes[i].ss) + table_floats(live, &live->nodes[i].ms));
    return n;
}

static unsigned char *put(unsigned char *out, const void *v, size_t n)
{
    memcpy(out, v, n);
    return out + n;
}

static void payload_write(const fm_sky_live *live, unsigned char *out)
{
    layout l = layout_of(live);
    out = put(out, &l, sizeof l);
    for (int i = 0; i < live->count; i++) {
        const live_node *n = &live->nodes[i];
        int32_t paths = n->paths_per_node;
        out = put(out, &n->sun_elevation_deg, sizeof(double));
        out = put(out, &paths, sizeof paths);
        out = put(out, n->ss.values, sizeof(float) * table_floats(live, &n->ss));
        out = put(out, n->ms.values, sizeof(float) * table_floats(live, &n->ms));
    }
}

static const unsigned char *get(const unsigned char *in, void *v, size_t n)
{
    memcpy(v, in, n);
    return in + n;
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
        int32_t paths;
        in = get(in, &e, sizeof e);
        in = get(in, &paths, sizeof paths);
        if (e != n->sun_elevation_deg || paths < 0)
            return "tables of other sun elevations";
        n->paths_per_node = paths;
        in = get(in, n->ss.values, sizeof(float) * table_floats(live, &n->ss));
        in = get(in, n->ms.values, sizeof(float) * table_floats(live, &n->ms));
        if (!all_finite(n->ss.values, table_floats(live, &n->ss)) ||
            !all_finite(n->ms.values, table_floats(live, &n->ms)))
            return "a value that is not a number";
    }
    return NULL;
}

/* ---- the file -------------------------------------------------------------------------------- */

typedef struct live_header {
    char magic[8];
    uint32_t version, byte_order;
    char key[32];
    uint64_t bytes, checksum;
} live_header;

#define HEADER_BYTES (8 + 4 + 4 + 32 + 8 + 8)

static void header_pack(const live_header *h, unsigned char *out)
{
    out = put(out, h->magic, 8);
    out = put(out, &h->version, 4);
    out = put(out, &h->byte_order, 4);
    out = put(out, h->key, 32);
    out = put(out, &h->bytes, 8);
    put(out, &h->checksum, 8);
}

static void header_unpack(const unsigned char *in, live_header *h)
{
    in = get(in, h->magic, 8);
    in = get(in, &h->version, 4);
    in = get(in, &h->byte_order, 4);
    in = get(in, h->key, 32);
    in = get(in, &h->bytes, 8);
    get(in, &h->checksum, 8);
}

static fm_status write_all(const char *tmp, const unsigned char *head, const unsigned char *body, size_t n)
{
    FILE *f = platform_fopen(tmp, "wb");
    if (!f)
        return FM_ERR_IO;
    int ok = fwrite(head, 1, HEADER_BYTES, f) == HEADER_BYTES && (n == 0 || fwrite(body, 1, n, f) == n);
    ok = fclose(f) == 0 && ok;
    return ok ? FM_OK : FM_ERR_IO;
}

fm_status fm_sky_live_save(const fm_sky_live *live, const char *path, fm_error *err)
{
    if (!path || !path[0])
        return fm_fail(err, FM_ERR_IO, "cannot write the live sky: no path");
    size_t n = payload_size(live);
    unsigned char *body = malloc(n);
    char *tmp = malloc(strlen(path) + 8);
    if (!body || !tmp) {
        free(body);
        free(tmp);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    }
    payload_write(live, body);
    live_header h = {.version = FILE_VERSION, .byte_order = BYTE_ORDER_MARK, .bytes = n,
                     .checksum = hash_bytes(body, n, CHECKSUM_SEED)};
    memcpy(h.magic, MAGIC, 8);
    char key[33];
    fm_sky_live_key(&live->params, key);
    memcpy(h.key, key, 32);
    unsigned char head[HEADER_BYTES];
    header_pack(&h, head);
    fm_status s = FM_OK;
    sprintf(tmp, "%s.XXXXXX", path);
    if (platform_create_unique(tmp) != 0)
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    else if (write_all(tmp, head, body, n) || platform_rename_replace(tmp, path) != 0) {
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
        platform_remove(tmp);
    }
    free(body);
    free(tmp);
    return s;
}

/* The whole file, or NULL (err filled). */
static unsigned char *read_all(const char *path, size_t *n, fm_error *err)
{
    FILE *f = platform_fopen(path, "rb");
    if (!f) {
        fm_fail(err, FM_ERR_IO, "cannot read '%s': %s", path, strerror(errno));
        return NULL;
    }
    size_t cap = 1 << 16, len = 0;
    unsigned char *buf = malloc(cap);
    while (buf) {
        len += fread(buf + len, 1, cap - len, f);
        if (len < cap)
            break;
        unsigned char *more = realloc(buf, cap *= 2);
        if (!more)
            free(buf);
        buf = more;
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf)
        fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory reading '%s'", path);
    else if (bad) {
        fm_fail(err, FM_ERR_IO, "cannot read '%s'", path);
        free(buf);
        buf = NULL;
    }
    *n = len;
    return buf;
}

/* Why the file cannot be this atmosphere's live sky, or NULL when it can. */
static const char *refusal(const live_header *h, size_t file_bytes, const char *key, const unsigned char *body)
{
    if (file_bytes < HEADER_BYTES || memcmp(h->magic, MAGIC, 8) != 0)
        return "not a live sky file";
    if (h->version != FILE_VERSION || h->byte_order != BYTE_ORDER_MARK)
        return "written by another version or machine";
    if (memcmp(h->key, key, 32) != 0)
        return "the tables of another atmosphere";
    if (h->bytes != file_bytes - HEADER_BYTES)
        return "truncated or extended";
    if (hash_bytes(body, (size_t)h->bytes, CHECKSUM_SEED) != h->checksum)
        return "corrupt (checksum)";
    return NULL;
}

fm_status fm_sky_live_load(const fm_sky_params *params, const char *path, fm_sky_live **out, fm_error *err)
{
    *out = NULL;
    size_t n;
    unsigned char *file = read_all(path, &n, err);
    if (!file)
        return err ? err->status : FM_ERR_IO;
    live_header h = {0};
    if (n >= HEADER_BYTES)
        header_unpack(file, &h);
    char key[33];
    fm_sky_live_key(params, key);
    fm_sky_live *live = NULL;
    const char *why = refusal(&h, n, key, file + HEADER_BYTES);
    fm_status s = why ? FM_ERR_INVALID_ARGUMENT : live_alloc(params, &live, err);
    if (!s && (why = payload_read(live, file + HEADER_BYTES, n - HEADER_BYTES)))
        s = FM_ERR_INVALID_ARGUMENT;
    if (why)
        fm_fail(err, s, "live sky '%s': %s", path, why);
    free(file);
    if (s) {
        fm_sky_live_destroy(live);
        return s;
    }
    *out = live;
    return FM_OK;
}

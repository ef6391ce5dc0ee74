#include "aerosol/cloud_optics.h"

#include "base/hash.h"
#include "base/sealed_file.h"
#include "base/status.h"
#include "base/threads.h"
#include "data/tables.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bump when the payload's meaning changes without the key's inputs changing. */
#define TABLE_VERSION 1u

static const sealed_format CLOUD_FORMAT = {{'F', 'M', 'C', 'L', 'O', 'U', 'D', '\n'}, TABLE_VERSION,
                                           0x636c6f7564ull /* "cloud" */, "cloud optics",
                                           "the optics of another cloud or grid"};

/* ---- the key ---------------------------------------------------------------------------------- */

/* A small droplet spectrum (size parameters below 35 at 550 nm: well under a millisecond) whose
 * optics fingerprint the Mie solver, its quadrature and the index interpolation. */
static const cloud_type PROBE = {"probe", 0, {2.0, 1.5, 1.0, 0.02, 3.0}, "solver fingerprint"};

static void hash_into(uint64_t h[2], const void *data, size_t n)
{
    h[0] = hash_bytes(data, n, h[0]);
    h[1] = hash_bytes(data, n, h[1]);
}

static void table_key(const cloud_type *t, const spectral_grid *grid, char out[33])
{
    uint64_t h[2] = {1, 2};
    const int32_t head[3] = {(int32_t)TABLE_VERSION, CLOUD_ANGLE_COUNT, grid->count};
    hash_into(h, head, sizeof head);
    const double size[5] = {t->size.alpha, t->size.b, t->size.gamma, t->size.r_min_um, t->size.r_max_um};
    hash_into(h, size, sizeof size);
    hash_into(h, grid->lambda_nm, sizeof(double) * (size_t)grid->count);
    hash_into(h, fm_water_index, sizeof(double) * 3 * FM_WATER_INDEX_COUNT);
    double probe[CLOUD_ANGLE_COUNT + 3] = {0};
    mie_lognormal_result r = {0};
    if (cloud_water_optics(&PROBE, 550.0, &r, probe + 3, NULL) == FM_OK) {
        probe[0] = r.ext_m2;
        probe[1] = r.sca_m2;
        probe[2] = r.g;
    }
    hash_into(h, probe, sizeof probe);
    snprintf(out, 33, "%016llx%016llx", (unsigned long long)h[0], (unsigned long long)h[1]);
}

static int path_for(const char *cache_dir, const char *key, char *out, size_t size)
{
    int n = snprintf(out, size, "%s/cloud-%s.fmcloud", cache_dir, key);
    return n > 0 && (size_t)n < size ? 0 : -1;
}

int cloud_water_table_path(const cloud_type *t, const spectral_grid *grid, const char *cache_dir, char *out,
                           size_t size)
{
    char key[33];
    table_key(t, grid, key);
    return path_for(cache_dir, key, out, size);
}

/* ---- computing -------------------------------------------------------------------------------- */

typedef struct water_job {
    const cloud_type *type;
    const spectral_grid *grid;
    mie_lognormal_result *result; /* [K] */
    double *phase;                /* [K][CLOUD_ANGLE_COUNT] */
    int failed;
} water_job;

static void water_items(void *ctx, int64_t begin, int64_t end, int thread)
{
    (void)thread;
    water_job *jb = ctx;
    for (int64_t k = begin; k < end; k++)
        if (cloud_water_optics(jb->type, jb->grid->lambda_nm[k], &jb->result[k],
                               jb->phase + (size_t)k * CLOUD_ANGLE_COUNT, NULL))
            jb->failed = 1;
}

static fm_status compute(const cloud_type *t, const spectral_grid *grid, int threads, cloud_water_table *out,
                         fm_error *err)
{
    mie_lognormal_result r550, result[FM_MAX_WAVELENGTHS];
    fm_status s = cloud_water_optics(t, 550.0, &r550, NULL, err);
    if (s)
        return s;
    water_job jb = {t, grid, result, out->phase, 0};
    s = parallel_for(threads, grid->count, 1, water_items, &jb, NULL, NULL);
    if (!s && jb.failed)
        s = fm_fail(err, FM_ERR_INTERNAL, "Mie integration failed for cloud type '%s'", t->name);
    for (int k = 0; !s && k < grid->count; k++) {
        out->ext_rel[k] = result[k].ext_m2 / r550.ext_m2;
        out->ssa[k] = result[k].sca_m2 / result[k].ext_m2;
    }
    return s;
}

/* ---- the file --------------------------------------------------------------------------------- */

static size_t payload_bytes(int K)
{
    return sizeof(double) * (size_t)K * (2 + CLOUD_ANGLE_COUNT);
}

static void payload_write(const cloud_water_table *tb, unsigned char *out)
{
    size_t K = (size_t)tb->count;
    memcpy(out, tb->ext_rel, sizeof(double) * K);
    memcpy(out + sizeof(double) * K, tb->ssa, sizeof(double) * K);
    memcpy(out + sizeof(double) * 2 * K, tb->phase, sizeof(double) * K * CLOUD_ANGLE_COUNT);
}

/* 1 when the file's payload fits the table and holds only possible values (then copied into it). */
static int payload_read(cloud_water_table *tb, const unsigned char *in, size_t bytes)
{
    size_t K = (size_t)tb->count, n = K * (2 + CLOUD_ANGLE_COUNT);
    if (bytes != payload_bytes(tb->count))
        return 0;
    for (size_t i = 0; i < n; i++) { /* extinction ratios > 0, albedos in (0, 1], phase >= 0 */
        double v;
        memcpy(&v, in + sizeof v * i, sizeof v);
        if (!(isfinite(v) && (i < K ? v > 0.0 : i < 2 * K ? v > 0.0 && v <= 1.0 : v >= 0.0)))
            return 0;
    }
    memcpy(tb->ext_rel, in, sizeof(double) * K);
    memcpy(tb->ssa, in + sizeof(double) * K, sizeof(double) * K);
    memcpy(tb->phase, in + sizeof(double) * 2 * K, sizeof(double) * K * CLOUD_ANGLE_COUNT);
    return 1;
}

static int load(cloud_water_table *tb, const char *path, const char *key)
{
    unsigned char *body;
    size_t n;
    if (sealed_file_read(path, &CLOUD_FORMAT, key, &body, &n, NULL))
        return 0;
    int ok = payload_read(tb, body, n);
    free(body);
    return ok;
}

static void save(const cloud_water_table *tb, const char *cache_dir, const char *path, const char *key)
{
    unsigned char *body = malloc(payload_bytes(tb->count));
    if (body && sealed_file_make_dirs(cache_dir) == 0) {
        payload_write(tb, body);
        sealed_file_write(path, &CLOUD_FORMAT, key, body, payload_bytes(tb->count), NULL);
    }
    free(body);
}

fm_status cloud_water_table_get(const cloud_type *t, const spectral_grid *grid, int threads, const char *cache_dir,
                                cloud_water_table *out, cloud_optics_source *source, fm_error *err)
{
    memset(out, 0, sizeof *out);
    if (t->ice)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "'%s' is an ice cloud", t->name);
    out->count = grid->count;
    out->phase = malloc(sizeof(double) * (size_t)grid->count * CLOUD_ANGLE_COUNT);
    if (!out->phase)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the cloud phase functions");
    char key[33], path[4096];
    int cached = cache_dir && cache_dir[0];
    if (cached) {
        table_key(t, grid, key);
        cached = path_for(cache_dir, key, path, sizeof path) == 0;
    }
    if (source)
        *source = CLOUD_OPTICS_FROM_CACHE;
    if (cached && load(out, path, key))
        return FM_OK;
    if (source)
        *source = CLOUD_OPTICS_COMPUTED;
    fm_status s = compute(t, grid, threads, out, err);
    if (s) {
        cloud_water_table_free(out);
        return s;
    }
    if (cached)
        save(out, cache_dir, path, key);
    return FM_OK;
}

void cloud_water_table_free(cloud_water_table *table)
{
    free(table->phase);
    table->phase = NULL;
}

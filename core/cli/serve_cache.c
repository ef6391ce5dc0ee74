#include "serve_cache.h"

#include "report.h"

#include "base/platform.h"
#include "base/sealed_file.h"
#include "base/text.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct slot {
    char key[33];
    fm_sky_live *live; /* NULL: empty */
    unsigned long used; /* the cache's clock when last asked for */
} slot;

struct live_cache {
    char *dir; /* NULL: no disk cache */
    int keep;
    slot *slots;
    unsigned long clock;
};

const char *live_source_name(live_source s)
{
    return s == LIVE_FROM_MEMORY ? "memory" : s == LIVE_FROM_DISK ? "disk" : "built";
}

const char *live_band_name(live_band b)
{
    return b == LIVE_BAND_BUILT ? "built" : b == LIVE_BAND_READY ? "ready" : "pending";
}

live_cache *live_cache_open(const char *dir, int keep)
{
    live_cache *c = calloc(1, sizeof *c);
    if (!c || !(c->slots = calloc((size_t)(keep > 1 ? keep : 1), sizeof *c->slots))) {
        free(c);
        return NULL;
    }
    c->keep = keep > 1 ? keep : 1;
    if (dir && !(c->dir = text_copy(dir))) {
        live_cache_close(c);
        return NULL;
    }
    if (c->dir && sealed_file_make_dirs(c->dir) != 0) { /* the server still runs, cold at every start */
        report_error("serve: cannot create the cache folder '%s' (%s); atmospheres are kept in memory only", c->dir,
                     strerror(errno));
        free(c->dir);
        c->dir = NULL;
    }
    return c;
}

void live_cache_close(live_cache *c)
{
    if (!c)
        return;
    for (int i = 0; c->slots && i < c->keep; i++)
        fm_sky_live_destroy(c->slots[i].live);
    free(c->slots);
    free(c->dir);
    free(c);
}

/* dir/KEY.fmlive (malloc'd), or NULL without a disk cache or memory. */
static char *cache_file(const live_cache *c, const char *key)
{
    if (!c->dir)
        return NULL;
    size_t n = strlen(c->dir) + strlen(key) + 16;
    char *p = malloc(n);
    if (p)
        snprintf(p, n, "%s/%s.fmlive", c->dir, key);
    return p;
}

/* The slot for a new atmosphere: an empty one, else the least recently used, emptied. */
static slot *free_slot(live_cache *c)
{
    slot *oldest = &c->slots[0];
    for (int i = 0; i < c->keep; i++) {
        if (!c->slots[i].live)
            return &c->slots[i];
        if (c->slots[i].used < oldest->used)
            oldest = &c->slots[i];
    }
    fm_sky_live_destroy(oldest->live);
    oldest->live = NULL;
    return oldest;
}

/* The atmosphere's tables into its cache file, when there is a folder (the server goes on when they
 * cannot be saved: cold next time). */
static void save(const fm_sky_live *live, const char *path)
{
    fm_error unsaved = {0};
    if (path && fm_sky_live_save(live, path, &unsaved))
        report_error("serve: cannot save the atmosphere to the cache: %s", unsaved.message);
}

/* The atmosphere of params (its key, its cache file path or NULL) from memory, the disk or a build
 * (then saved). */
static fm_status find(live_cache *c, const fm_sky_params *params, const char *key, const char *path,
                      const atomic_int *cancel, fm_sky_live **out, live_source *source, fm_error *err)
{
    for (int i = 0; i < c->keep; i++)
        if (c->slots[i].live && strcmp(c->slots[i].key, key) == 0) {
            c->slots[i].used = c->clock;
            *out = c->slots[i].live;
            *source = LIVE_FROM_MEMORY;
            return FM_OK;
        }
    slot *s = free_slot(c);
    fm_sky_live *live = NULL;
    *source = LIVE_FROM_DISK;
    if (path && platform_path_kind(path) == PLATFORM_FILE) {
        fm_error refused = {0};
        if (fm_sky_live_load(params, path, &live, &refused)) {
            report_error("serve: cache file '%s' refused (%s); rebuilding it", path, refused.message);
            live = NULL;
        }
    }
    if (!live) {
        *source = LIVE_BUILT;
        fm_status st = fm_sky_live_create(params, cancel, &live, err);
        if (st)
            return st;
        save(live, path);
    }
    memcpy(s->key, key, sizeof s->key);
    s->live = live;
    s->used = c->clock;
    *out = live;
    return FM_OK;
}

fm_status live_cache_get(live_cache *c, const fm_sky_params *params, double sun_elevation_deg,
                         const atomic_int *cancel, fm_sky_live **out, live_source *source, live_band *band,
                         fm_error *err)
{
    char key[33];
    fm_sky_live_key(params, key);
    fm_sky_params p = *params; /* the cloud optics go to the server's cache folder too, or nowhere */
    p.cache_dir = c->dir;
    c->clock++;
    char *path = cache_file(c, key);
    fm_sky_live *live = NULL;
    int built = 0;
    *band = LIVE_BAND_READY;
    fm_status s = find(c, &p, key, path, cancel, &live, source, err);
    if (!s && !fm_sky_live_is_complete(live))
        s = fm_sky_live_prepare(live, sun_elevation_deg, cancel, &built, err);
    if (!s && built) /* the file completed: replaced whole (fm_sky_live_save) */
        save(live, path);
    if (!s && !fm_sky_live_is_complete(live))
        *band = LIVE_BAND_PENDING;
    else if (!s && built)
        *band = LIVE_BAND_BUILT;
    free(path);
    *out = live;
    return s;
}

fm_status live_cache_refine(live_cache *c, fm_sky_live *live, const atomic_int *cancel, fm_error *err)
{
    for (int i = 0; i < c->keep; i++)
        if (live && c->slots[i].live == live) {
            fm_status s = fm_sky_live_refine(live, cancel, err);
            char *path = s ? NULL : cache_file(c, c->slots[i].key);
            save(live, path);
            free(path);
            return s;
        }
    return FM_OK;
}

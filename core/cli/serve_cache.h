/* The built atmospheres of `firmament serve` (fm_sky_live): the last few used in memory, and every
 * one on disk in a cache folder under its key (fm_sky_live_key), so that a new server starts warm.
 * A cache file the library refuses (corrupt, truncated, another version's) is rebuilt and replaced,
 * never used.  fm_sky_live_save writes a file whole or not at all.  An atmosphere is built without
 * its twilight band (the suns below the horizon), which the first request for a sun that reads it
 * builds (fm_sky_live_create); its file, saved before, is then replaced by one that holds the band. */
#ifndef FM_CLI_SERVE_CACHE_H
#define FM_CLI_SERVE_CACHE_H

#include "firmament/firmament.h"

#include <stddef.h>

typedef enum live_source { LIVE_FROM_MEMORY, LIVE_FROM_DISK, LIVE_BUILT } live_source;

/* The twilight band (the suns below the horizon) after a request: built by it, built before, or
 * still to be built. */
typedef enum live_band { LIVE_BAND_BUILT, LIVE_BAND_READY, LIVE_BAND_PENDING } live_band;

typedef struct live_cache live_cache;

/* dir: the cache folder (created with its parents when missing), or NULL for none; keep: the
 * atmospheres kept in memory, at least 1.  NULL when out of memory. */
live_cache *live_cache_open(const char *dir, int keep);
void live_cache_close(live_cache *c); /* accepts NULL */

/* The built atmosphere of params (its sun already resolved: fm_sky_params_resolve_sun), from
 * memory, the disk or a build (then saved), with the tables a map at sun_elevation_deg reads (the
 * twilight band built when pending and read: then saved again); owned by the cache, valid
 * until the next call.  On failure *out is NULL, or an atmosphere whose band is still pending. */
fm_status live_cache_get(live_cache *c, const fm_sky_params *params, double sun_elevation_deg,
                         const atomic_int *cancel, fm_sky_live **out, live_source *source, live_band *band,
                         fm_error *err);

/* One round of refinement (fm_sky_live_refine) of live, an atmosphere of the cache, then its file
 * saved again (it holds the rounds, from which a new server resumes); FM_ERR_CANCELLED leaves both as
 * they were.  Nothing when live is not the cache's. */
fm_status live_cache_refine(live_cache *c, fm_sky_live *live, const atomic_int *cancel, fm_error *err);

/* "memory", "disk", "built" */
const char *live_source_name(live_source s);
/* "built", "ready", "pending" */
const char *live_band_name(live_band b);

#endif

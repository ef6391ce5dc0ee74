/* The live sky (fm_sky_live, docs/rendering.md "Live sky"): the fast path's two radiance tables
 * (single scattering, and the fitted multiple scattering) made once for each sun elevation of a
 * grid, from -20 to 90 degrees; a map for any sun interpolates the four nearest elevations'
 * tables and reads them at the azimuth relative to the sun, as the fast path reads its own.
 * live.c builds and renders, live_file.c saves and loads. */
#ifndef FM_RENDER_LIVE_H
#define FM_RENDER_LIVE_H

#include "firmament/firmament.h"
#include "render/live_tables.h"

#include <stddef.h>
#include <stdint.h>

/* The parameters a live sky builds its fm_sky from: the sun at a fixed place, no time of day, the
 * Earth-Sun distance of the date when it came from the time. */
fm_status live_sky_params(const fm_sky_params *params, fm_sky_params *out, fm_error *err);

/* A live sky for the atmosphere of params with its sky built and every node's tables allocated
 * (zero) at its sun elevation: for fm_sky_live_create to fill and for live_file.c to read into. */
fm_status live_alloc(const fm_sky_params *params, fm_sky_live **out, fm_error *err);

/* Fills the tables of the nodes from from_deg to to_deg and marks them built when all are
 * (fm_sky_live_create: all but the twilight band, made on first use; a test may build a few).
 * The deep twilight nodes' smoothing takes in the twilight nodes above them built before. */
fm_status live_build_nodes(fm_sky_live *live, double from_deg, double to_deg, const atomic_int *cancel,
                           fm_error *err);

/* Sets band_pending from the nodes' built flags: the twilight band is left for first use when
 * every other node is built and it is not (fm_sky_live_create, a file's tables); a test's few nodes
 * never build more themselves. */
void live_settle_pending(fm_sky_live *live);

#endif

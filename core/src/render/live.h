/* The live sky (fm_sky_live, docs/rendering.md "Live sky"): what live.c builds once per atmosphere
 * and live_file.c saves and loads. */
#ifndef FM_RENDER_LIVE_H
#define FM_RENDER_LIVE_H

#include "firmament/firmament.h"

#include <stddef.h>
#include <stdint.h>

/* Part of every key: a change of what the tables hold or how they are laid out makes old files
 * another atmosphere's. */
#define LIVE_TABLE_VERSION 1

struct fm_sky_live {
    fm_sky *sky;          /* the atmosphere; its sun is set per render on a copy */
    fm_sky_params params; /* as given to create, the sun and time resolved away (live.c) */
};

/* The parameters a live sky builds its fm_sky from: the sun at a fixed place, no time of day, the
 * Earth-Sun distance of the date when it came from the time. */
fm_status live_sky_params(const fm_sky_params *params, fm_sky_params *out, fm_error *err);

/* The live sky's tables as one block of bytes, for live_file.c: its size, the bytes, and a live sky
 * made from them (params: the atmosphere, whose key the file matched). */
size_t live_payload_size(const fm_sky_live *live);
void live_payload_write(const fm_sky_live *live, unsigned char *out);
fm_status live_from_payload(const fm_sky_params *params, const unsigned char *in, size_t n, fm_sky_live **out,
                            fm_error *err);

#endif

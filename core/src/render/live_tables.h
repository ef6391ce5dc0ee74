/* The live sky's tables (live.h): one node's per sun elevation of the grid, and the whole that
 * fm_sky_live is; a module of its own so that what works on the tables (live_smooth.h) does not
 * include the live sky's builder. */
#ifndef FM_RENDER_LIVE_TABLES_H
#define FM_RENDER_LIVE_TABLES_H

#include "firmament/firmament.h"
#include "render/aureole.h"
#include "render/ms_table.h"
#include "render/quality.h"
#include "transport/sky_grid.h"

#include <pthread.h>
#include <stdatomic.h>

/* Part of every key: a change of what the tables hold or how they are laid out makes old files
 * another atmosphere's. */
#define LIVE_TABLE_VERSION 22

/* How far apart the seeds of builds with other `seed`s lie: more than the nodes, so that no node's
 * seed is another build's. */
#define LIVE_SEED_STRIDE 1000u

/* The twilight band's rounds of refinement (fm_sky_live_refine) at most: each adds the build's
 * paths again with new seeds (docs/decisions/2026-12-07-live-refine.md). */
#define LIVE_REFINE_ROUNDS 8

/* How far apart the seeds of rounds lie: beyond every build's (LIVE_SEED_STRIDE times its `seed`). */
#define LIVE_ROUND_SEED_SHIFT 32

/* The tables of one sun elevation. */
typedef struct live_node {
    double sun_elevation_deg;
    int built;          /* its tables are made (live_build_nodes), or read from a file that held them */
    int paths_per_node; /* the multiple-scattering table's */
    sky_grid ss;        /* single scattering, logarithmic */
    sky_grid ms;        /* multiple scattering, fitted, linear */
    aureole aureole;    /* single scattering around the sun (aureole.h) */
} live_node;

/* fm_sky_params' strings (biome, clouds, atmosphere_file, presets_dir, cache_dir) */
#define LIVE_STRINGS 5

struct fm_sky_live {
    fm_sky *sky;          /* the atmosphere; its sun is set per render on a copy */
    fm_sky_params params; /* as given to create, the sun and time resolved away (live_sky_params); its
                           * strings are `strings`, the live sky's own copies (the sky's point there too) */
    char *strings[LIVE_STRINGS];
    char key[33]; /* fm_sky_live_key at create, what a saved file carries: the files it hashes as they were */
    quality_settings q;   /* the tables' (live.c) */
    fm_quality quality;   /* the level and sample scale the maps record */
    double sample_scale;
    int channels;         /* 3 (CIE XYZ) or 1 (a monochromatic sky) */
    int count;            /* nodes, by rising sun elevation */
    uint64_t seed;        /* 0: the product's paths; n moves every node's seed by n * LIVE_SEED_STRIDE,
                           * for measuring the spread of a build's noise (live-bench accuracy's seeds) */
    live_node *nodes;
    /* The twilight band's multiple-scattering paths before their fit (0 to the band's count - 1, as
     * nodes; parted above deep twilight, as their jobs' tables): sums over every round, the raw
     * estimates that a round of refinement adds to and refits; `paths` 0 until the band is built (and
     * in fog, whose tables are not refined). */
    ms_table *raw;
    int raw_count;
    int rounds; /* rounds of refinement in the band's tables (0: as built) */
    /* The twilight band is built on first use (live.c): while band_pending, a map whose sun reads
     * one of its nodes builds the band under `lock` first; the other nodes are never written then. */
    atomic_int band_pending;
    pthread_mutex_t lock;
};

#endif

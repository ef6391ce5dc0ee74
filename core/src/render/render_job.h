/* What the parts of a render share: the sky, the camera, the settings, the seed, the tables of the
 * fast path and the image being made (render.c builds it; ms_table.c and reference.c work on it). */
#ifndef FM_RENDER_RENDER_JOB_H
#define FM_RENDER_RENDER_JOB_H

#include "base/units.h"
#include "camera/camera.h"
#include "render/aureole.h"
#include "render/channels.h"
#include "render/quality.h"
#include "transport/deck_base.h"
#include "transport/ground_irradiance.h"
#include "transport/sky_grid.h"
#include "transport/twilight.h"

#include <assert.h>
#include <math.h>
#include <stdatomic.h>

/* Seeds: every random stream is (seed, item, sample) with disjoint item ranges per use, and the
 * wavelength set mixed into the seed so renders at different wavelengths draw independent numbers. */
#define ITEM_MS_NODE 0x100000000ull
#define ITEM_PIXEL 0x200000000ull

typedef struct render_job {
    const fm_sky *sky;
    const fm_render_params *params;
    quality_settings q;
    uint64_t seed;
    int channels;
    camera cam;
    const twilight_sampling *twilight; /* below the horizon only (twilight.h) */
    const shadow_flight_columns *shared_flights; /* the live sky's, for its deep twilight nodes; else NULL */
    sky_grid ss;                       /* the single-scattering table */
    struct ms_table *ms;               /* the multiple-scattering table (ms_table.h) */
    const aureole *aureole;            /* the live sky's around the sun (aureole.h), else NULL */
    aureole_frame aureole_frame;       /* its sun's */
    const sky_grid *ms_grid;           /* the pixels' multiple-scattering radiance (ms->grid, or the live
                                        * sky's, live.c) */
    int paths_per_node;                /* the multiple-scattering table's, once filled */
    ground_irradiance ground;
    deck_base deck;                    /* under a deck (deck_base_for_sky), else zeroed */
    const deck_base *under_deck;       /* &deck when built, else NULL: the paths' path_context.deck */
    int fine_fog_table;                /* the caller takes a multiple-scattering table finer than the
                                        * quality's where fog fills it (fog_table_size; fm_render and
                                        * the live sky's nodes) */
    int fog_from_above;                /* the caller lets fog below FOG_TABLE_MIN_SUN_DEG take the column
                                        * lit by the sky above the fog (fog_table_from_above): fm_render,
                                        * not the live sky's nodes (a sky more to build per node) */
    int one_pass;                      /* the multiple-scattering table takes the quality's paths alone, no
                                        * deep twilight pass (ms_table.c): the skies above fog, whose
                                        * noise the fog averages over their whole sky */
    int ms_refine;                     /* > 1: the ground's irradiance from the table read through
                                        * sky_grid_refine by this factor (the live sky's nodes, whose
                                        * maps read it so too: live.c) */
    fm_image *img;
    atomic_int no_memory; /* a worker could not allocate */
} render_job;

/* The direction at an elevation and an azimuth relative to the sun's (rad). */
static inline vec3 render_view_direction(const fm_sky *sky, double elevation, double rel_azimuth)
{
    vec3 d = direction_from_elevation_azimuth(elevation, sky->params.sun_azimuth_deg * FM_DEG + rel_azimuth);
    assert(fabs(v3_length(d) - 1.0) < 1e-12);
    return d;
}

/* An azimuth (rad, from north toward east) relative to the sun's, folded into [0, pi]. */
static inline double render_relative_azimuth(const fm_sky *sky, double azimuth)
{
    double phi = fmod(azimuth - sky->params.sun_azimuth_deg * FM_DEG, 2.0 * FM_PI);
    if (phi < 0.0)
        phi += 2.0 * FM_PI;
    return phi > FM_PI ? 2.0 * FM_PI - phi : phi;
}

#endif

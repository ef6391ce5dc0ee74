/* Which sky takes the column (render/fog_table.h) instead of the path tracer's table, and how it is
 * lit: one classification of a render job into a named regime from the sky's layers, the observer
 * and the sun, driven by one table of bounds (fog_regime.c; each bound's why in its comment below
 * and the decision record it comes from).  fog_table_applies and the other predicates read it. */
#ifndef FM_RENDER_FOG_REGIME_H
#define FM_RENDER_FOG_REGIME_H

#include "firmament/firmament.h"

struct render_job;

/* Fog of this visibility or less (extinction 3.912 / V at 550 nm) takes the column: a view in it sees
 * a few hundred metres, where the sphere does not matter. */
#define FOG_TABLE_MAX_VISIBILITY_M 1000.0
/* A cloud layer above the observer (or around an observer above the ground) of this optical depth
 * at 550 nm or more takes the column too: its paths random-walk through the layer. */
#define FOG_TABLE_MIN_TAU 2.0
/* Without such a layer, the lowest of this optical depth or more (a thin veil: the paths' noise is
 * half a percent at 0.25 and rises to 2-8 % at 2), with the sun FOG_TABLE_THIN_MIN_SUN_DEG up or
 * more (below). */
#define FOG_TABLE_MIN_TAU_THIN 0.1
/* The sun at least this high: with the beam pseudo-spherical above the fog and the air in thin
 * layers the column is within 2 % (plus 3 standard errors) of the path tracer from sun 0.2 degrees
 * up but for a view or two (docs/decisions/2026-12-06-fog-column.md); at the horizon the plane's
 * beam has no cosine. */
#define FOG_TABLE_MIN_SUN_DEG 0.2
/* With another cloud layer above the fog or the deck a lower sun keeps the paths (at 3 degrees under a
 * cirrostratus the diffuse light came out 50 times too bright when the air layers' beam cosines came
 * from the points above one another; now from the ray to the column's top, fog_column.c), but for thin
 * layers above an elevated deck, which takes the column lit from above below its own bound as a deck
 * alone does (docs/decisions/2026-12-07-two-layers-low-sun.md). */
#define FOG_TABLE_MIN_SUN_DEG_CLOUDS 8.0
/* Under an elevated layer the sun at least this many degrees per km of the layer's base: one sun
 * lights the whole plane, while the deck a view meets d km away is lit by a sun d / R higher or
 * lower (1.75 degrees at the horizon under a base at 3 km).  Near the sun, where a layer's forward
 * light follows the sun's elevation steeply, a cirrostratus at 8 km was 12-16 % dark at sun 3 and
 * up to 10 % at sun 8 (docs/decisions/2026-12-06-cloud-column.md); decks up to 4 km at sun 3 agree
 * within the reference's noise but for the horizon away from the sun. */
#define FOG_TABLE_MIN_SUN_DEG_PER_KM 1.0
/* A thin layer (FOG_TABLE_MIN_TAU_THIN up to FOG_TABLE_MIN_TAU) with the sun at least this high: its
 * forward light near the sun, not hidden by the layer's own depth, is one beam's in the column, while
 * a view below the sun crosses more of the layer than one above it, and a view low toward the sun
 * meets a high layer where the sun stands higher.  At sun 24 cirrostratus (optical depth 0.5 and 1)
 * and altostratus (1) were within 2 % plus 3 standard errors of the reference in every view; at 9.5
 * altostratus (1) was 23 % bright 3.5 degrees below the sun and 10 % dark 4.5 above it
 * (docs/decisions/2026-12-07-thin-layers.md).  A thin layer of ice alone over an observer on the
 * ground takes the column below it down to FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG at several suns, each view
 * lit by the sun where it meets the layer (render/fog_local_sun.h): cirrostratus at sun 3 to 10 within
 * the reference's tolerance but for a view (docs/decisions/2026-12-07-thin-layers-low-sun.md).
 * Droplets keep this bound: their truncated peak's light, about the sun, stays the observer's sun's
 * (altostratus of 1 at sun 15: 11 % dark 9 degrees below the sun with the several suns).  Fog alone
 * around the observer of FOG_TABLE_MIN_TAU_FOG or more does not: it is around the observer at the
 * observer's sun (Misty morning: 100 m of 400 m visibility, optical depth 0.98, sun 12.4). */
#define FOG_TABLE_THIN_MIN_SUN_DEG 24.0
/* Lower, the thinner ice layers miss the reference at the horizon near the sun (cirrostratus of 0.5
 * at sun 2: 17 % dark 6 degrees from the sun; of 1, within the tolerance down to sun 1). */
#define FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG 3.0
/* A layer of ice of FOG_TABLE_THIN_LOW_SUN_MIN_TAU or more takes it down to this sun: cirrostratus of
 * 1 and 1.9 at sun 1 within the tolerance in every view, of 0.75 at sun 1 and of 1 at sun 0.5 15-18 %
 * dark 4-8 degrees above the sun (docs/decisions/2026-12-07-thin-layers-twilight.md). */
#define FOG_TABLE_THIN_LOW_SUN_DEG 1.0
#define FOG_TABLE_THIN_LOW_SUN_MIN_TAU 1.0
/* Fog alone around the observer thinner than FOG_TABLE_MIN_TAU but of FOG_TABLE_MIN_TAU_FOG or more
 * takes the column from FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG (and below 3, lit from above); thinner fog
 * keeps FOG_TABLE_THIN_MIN_SUN_DEG.  The column's light near the sun is one beam's, and less fog
 * hides it less (4 degrees above the sun at sun 12: +5 % at 0.39 and 0.59, +1.6 % at 0.98), the more
 * so at a low sun (2.5 degrees above a sun of 3.5: -18 % at 0.39, -14 % at 0.85, -8.5 % at 0.98).
 * Bounds chosen from those measurements (docs/decisions/2026-12-07-shallow-fog.md), not fits. */
#define FOG_TABLE_MIN_TAU_FOG 0.8
#define FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG 6.0
/* Above a deck (a layer of FOG_TABLE_MIN_TAU or more below the observer, alone) below this sun the
 * column is made at several suns, each view down lit by the sun where it meets the deck's top. */
#define FOG_TABLE_ABOVE_LOCAL_SUN_DEG 10.0
/* Shallow fog around the observer under thin layers only (fog 0-100 m of visibility 400 m under
 * cirrostratus): the column lit from above below FOG_TABLE_FOG_UNDER_THIN_SUN_DEG, blended with the
 * day's up to FOG_TABLE_BLEND_DEG above it, the paths below FOG_TABLE_FOG_UNDER_THIN_MIN_SUN_DEG.  The
 * day's column alone was 2-10 % bright at sun 10 (its one sun for the distant layer above), the
 * column lit from above 11-12 % dark 12 degrees above a sun of 3 and 1; both within 2 % + 3 se
 * between (docs/decisions/2026-12-07-fog-under-thin-layers.md).  Measured points, not fits. */
#define FOG_TABLE_FOG_UNDER_THIN_SUN_DEG 12.0
#define FOG_TABLE_FOG_UNDER_THIN_MIN_SUN_DEG 5.0

/* Below FOG_TABLE_MIN_SUN_DEG, down to the end of astronomical twilight, fog alone around an observer
 * on the ground (below FOG_TABLE_ON_GROUND_M), or a deck alone (or under thin layers) above it (below
 * FOG_TABLE_MIN_SUN_DEG_PER_KM per km of its base; above FOG_TABLE_FROM_ABOVE_MAX_BASE_M at several
 * suns, fog_table_local_sun), takes the
 * column of the layer and the air under it lit from above by the spherical sky without the layer
 * (render/fog_incident.h) and, with the sun up, by the beam at the layer's top
 * (docs/decisions/2026-12-07-twilight-fog.md), where the job lets it (fog_from_above).  For
 * FOG_TABLE_BLEND_DEG above that the table is that column's and the day's blended, its share falling
 * linearly from 1 to 0: in fog the two differ by about 3 % (the day's column a percent or two bright
 * of the reference, this one as dark), which would be a jump. */
#define FOG_TABLE_TWILIGHT_MIN_SUN_DEG (-18.0)
#define FOG_TABLE_BLEND_DEG 2.8
/* in fog: FOG_TABLE_MIN_SUN_DEG + FOG_TABLE_BLEND_DEG */
#define FOG_TABLE_BLEND_TO_DEG 3.0
/* A deck's field comes from the sky above the observer, but a view meets the deck d km away, under a
 * sun d / R higher or lower: at twilight the sky brightens by some 0.5 % per 0.01 degrees, so with one
 * sun a view 10 degrees up meeting a deck at 3 km (17 km off, 0.15 degrees) was 7 to 12 % off
 * (altostratus at sun -1); at 1 km a third of that, so one sun does up to here and a higher base
 * takes the column at several suns (render/fog_local_sun.h), three times the incident skies. */
#define FOG_TABLE_FROM_ABOVE_MAX_BASE_M 1000.0
#define FOG_TABLE_ON_GROUND_M 0.5

/* How the job's multiple-scattering table is made. */
typedef enum fog_regime {
    FOG_REGIME_PATHS,           /* the path tracer's table (no column) */
    FOG_REGIME_DAY,             /* the day's column: the beam and the air above, one sun */
    FOG_REGIME_DAY_THIN_SUNS,   /* the day's column at several suns under a thin layer of ice alone */
    FOG_REGIME_DAY_ABOVE_SUNS,  /* the day's column at several suns, views down to a deck below */
    FOG_REGIME_FROM_ABOVE,      /* the column lit from above (blended with the day's by its share) */
    FOG_REGIME_FROM_ABOVE_SUNS, /* the same at several suns, under a deck above
                                 * FOG_TABLE_FROM_ABOVE_MAX_BASE_M */
    FOG_REGIME_COUNT
} fog_regime;

/* What the column holds, the sun aside: the sky's layers about the observer.  The rows of the table
 * of bounds (fog_regime.c). */
typedef enum fog_layers {
    FOG_LAYERS_NONE,            /* no layer the column takes */
    FOG_LAYERS_FOG,             /* fog alone around the observer, FOG_TABLE_MIN_TAU or more */
    FOG_LAYERS_SHALLOW_FOG,     /* fog alone around the observer, FOG_TABLE_MIN_TAU_FOG up to MIN_TAU */
    FOG_LAYERS_THIN_FOG,        /* fog alone around the observer, thinner */
    FOG_LAYERS_DECK,            /* a layer of FOG_TABLE_MIN_TAU or more alone, above or around the observer */
    FOG_LAYERS_DECK_BELOW,      /* such a layer alone below the observer */
    FOG_LAYERS_DECK_UNDER_THIN, /* an elevated deck with only thin layers, all above its top */
    FOG_LAYERS_FOG_UNDER_THIN,  /* shallow fog around the observer with only thin layers above */
    FOG_LAYERS_THIN_ICE,        /* a thin layer of ice alone over an observer on the ground, of
                                 * FOG_TABLE_THIN_LOW_SUN_MIN_TAU or more */
    FOG_LAYERS_THIN_ICE_VEIL,   /* the same, thinner */
    FOG_LAYERS_THIN,            /* any other sky whose column's layer is thinner than FOG_TABLE_MIN_TAU */
    FOG_LAYERS_MIXED,           /* any other sky with a layer of FOG_TABLE_MIN_TAU (or fog) and others */
    FOG_LAYERS_COUNT
} fog_layers;

/* A render job as the classification reads it (fog_scene_of builds it from a job). */
typedef struct fog_scene_layer {
    double base_m, thickness_m, tau550; /* m above the ground; optical depth at 550 nm */
    int ice;                            /* ice crystals (cloud_type.ice) */
} fog_scene_layer;

typedef struct fog_scene {
    int layer_count;
    fog_scene_layer layer[FM_MAX_CLOUD_LAYERS];
    double altitude_m;     /* the observer above the ground */
    double sun_z;          /* the sun's direction's z: the sine of its elevation */
    int fog_from_above;    /* the caller lets the column lit from above take the table (render_job) */
    int twilight;          /* the job has twilight tables (render_job.twilight): no day's column */
    int under_deck;        /* the deck base takes the table (render_job.under_deck) */
    int reference;         /* reference quality: paths only */
} fog_scene;

void fog_scene_of(const struct render_job *job, fog_scene *scene);

/* The scene's layers (fog_layers) and the index of the layer the column is for (-1: none). */
fog_layers fog_scene_layers(const fog_scene *scene, int *cloud);
/* The scene's regime. */
fog_regime fog_scene_regime(const fog_scene *scene);
/* The column lit from above's share of the table at the scene's sun: 1 below its row's bound, falling
 * linearly to 0 over FOG_TABLE_BLEND_DEG above it (whatever the regime). */
double fog_scene_above_share(const fog_scene *scene);

/* The job's regime. */
fog_regime fog_regime_of(const struct render_job *job);
/* The layer the column is for (an index into sky->composition.cloud), or -1. */
int fog_regime_cloud(const fm_sky *sky);
/* fog_scene_above_share for the sky's own layers and sun (the job's flags aside). */
double fog_regime_above_share(const fm_sky *sky);

/* Reads of the regime.  Whether the job's table takes the column lit from above (wholly or blended),
 * and its share (0 where not). */
int fog_table_from_above(const struct render_job *job);
double fog_table_above_share(const struct render_job *job);
/* Whether that column is made at several suns, each view lit by the sun where it meets the deck
 * (fog_local_sun.h): a deck whose base is above FOG_TABLE_FROM_ABOVE_MAX_BASE_M. */
int fog_table_local_sun(const struct render_job *job);
/* Whether the job's table comes from the column (any regime but FOG_REGIME_PATHS).  The ground's
 * irradiance then takes orders >= 2 from the column too (build it without paths). */
int fog_table_applies(const struct render_job *job);
/* Whether the sky holds such fog or cloud (of FOG_TABLE_MIN_TAU, or fog of
 * FOG_TABLE_MAX_VISIBILITY_M) and no deck that the deck base takes by day (the rest of
 * fog_table_applies is the sun's and the job's): a live sky then sizes every node's table as the
 * column's (fog_table_size) and leaves its day nodes unsmoothed. */
int fog_table_sky(const fm_sky *sky);

#endif

#include "render/fog_regime.h"

#include "aerosol/cloud.h"
#include "base/units.h"
#include "base/vec.h"
#include "render/render_job.h"
#include "sky.h"

#include <math.h>

/* One row per fog_layers: the sun's bounds (degrees) of each way of making the table. */
typedef struct regime_bounds {
    /* the column lit from above, on the ground, from above_from_deg up to above_below_deg (or
     * FOG_TABLE_MIN_SUN_DEG_PER_KM per km of the layer's base, where above_per_km and higher), plus
     * FOG_TABLE_BLEND_DEG over which it is blended with the day's; none without above */
    int above;
    double above_from_deg, above_below_deg;
    int above_per_km;
    /* the day's column from day_min_deg up (day_min_lit_deg where the column lit from above could
     * take the layer below it, 0: the same), and FOG_TABLE_MIN_SUN_DEG_PER_KM per km of the layer's
     * base where day_per_km */
    double day_min_deg, day_min_lit_deg;
    int day_per_km;
    /* the day's column at several suns below this (0: none) */
    double day_suns_below_deg;
    fog_regime day_suns;
} regime_bounds;

#define TWILIGHT FOG_TABLE_TWILIGHT_MIN_SUN_DEG
#define NO_SUNS 0.0, FOG_REGIME_DAY

static const regime_bounds table[FOG_LAYERS_COUNT] = {
    [FOG_LAYERS_NONE] = {0, 0.0, 0.0, 0, 90.0, 0.0, 0, NO_SUNS},
    /* fog: the column from sun 0.2 (2026-12-06-fog-column.md), lit from above below it down to the
     * end of twilight (2026-12-07-twilight-fog.md) */
    [FOG_LAYERS_FOG] = {1, TWILIGHT, FOG_TABLE_MIN_SUN_DEG, 1, FOG_TABLE_MIN_SUN_DEG, 0.0, 1, NO_SUNS},
    /* shallow fog: the column's one beam near the sun is hidden less, so from sun 6
     * (2026-12-07-shallow-fog.md) */
    [FOG_LAYERS_SHALLOW_FOG] = {1, TWILIGHT, FOG_TABLE_MIN_SUN_DEG, 1, FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG, 0.0, 1,
                                NO_SUNS},
    /* thinner fog: a thin layer's bound, sun 24 (2026-12-07-thin-layers.md) */
    [FOG_LAYERS_THIN_FOG] = {1, TWILIGHT, FOG_TABLE_MIN_SUN_DEG, 1, FOG_TABLE_THIN_MIN_SUN_DEG, 0.0, 1, NO_SUNS},
    /* a deck: one sun lights the plane, a view meets the deck under a sun d / R off, so 1 degree per
     * km of its base (2026-12-06-cloud-column.md); lit from above below that (2026-12-07-twilight-fog.md) */
    [FOG_LAYERS_DECK] = {1, TWILIGHT, FOG_TABLE_MIN_SUN_DEG, 1, FOG_TABLE_MIN_SUN_DEG, 0.0, 1, NO_SUNS},
    /* above a deck: each view down at the sun where it meets the deck's top below sun 10
     * (2026-12-07-above-deck.md) */
    [FOG_LAYERS_DECK_BELOW] = {0, 0.0, 0.0, 0, FOG_TABLE_MIN_SUN_DEG, 0.0, 1, FOG_TABLE_ABOVE_LOCAL_SUN_DEG,
                               FOG_REGIME_DAY_ABOVE_SUNS},
    /* thin layers above a deck: as the deck alone where the column lit from above takes it below its
     * bound, else sun 8 as any two layers (2026-12-07-two-layers-low-sun.md) */
    [FOG_LAYERS_DECK_UNDER_THIN] = {1, TWILIGHT, FOG_TABLE_MIN_SUN_DEG, 1, FOG_TABLE_MIN_SUN_DEG_CLOUDS,
                                    FOG_TABLE_MIN_SUN_DEG, 1, NO_SUNS},
    /* shallow fog under thin layers: lit from above from sun 5 below 12, blended to 14.8, the day's
     * column above (2026-12-07-fog-under-thin-layers.md) */
    [FOG_LAYERS_FOG_UNDER_THIN] = {1, FOG_TABLE_FOG_UNDER_THIN_MIN_SUN_DEG, FOG_TABLE_FOG_UNDER_THIN_SUN_DEG, 0,
                                   FOG_TABLE_FOG_UNDER_THIN_SUN_DEG + FOG_TABLE_BLEND_DEG, 0.0, 0, NO_SUNS},
    /* a thin layer of ice alone: the day's column at several suns from sun 1 for optical depth 1 or
     * more (2026-12-07-thin-layers-twilight.md), one sun from 24 (2026-12-07-thin-layers.md) */
    [FOG_LAYERS_THIN_ICE] = {0, 0.0, 0.0, 0, FOG_TABLE_THIN_LOW_SUN_DEG, 0.0, 0, FOG_TABLE_THIN_MIN_SUN_DEG,
                             FOG_REGIME_DAY_THIN_SUNS},
    /* thinner ice: from sun 3 (2026-12-07-thin-layers-low-sun.md) */
    [FOG_LAYERS_THIN_ICE_VEIL] = {0, 0.0, 0.0, 0, FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG, 0.0, 0,
                                  FOG_TABLE_THIN_MIN_SUN_DEG, FOG_REGIME_DAY_THIN_SUNS},
    /* any other thin layer: its forward light near the sun is one beam's, so from sun 24
     * (2026-12-07-thin-layers.md) */
    [FOG_LAYERS_THIN] = {0, 0.0, 0.0, 0, FOG_TABLE_THIN_MIN_SUN_DEG, 0.0, 1, NO_SUNS},
    /* other layers with a thick one: from sun 8, where the air layers' beam holds
     * (2026-12-07-two-layers-low-sun.md) */
    [FOG_LAYERS_MIXED] = {0, 0.0, 0.0, 0, FOG_TABLE_MIN_SUN_DEG_CLOUDS, 0.0, 1, NO_SUNS},
};

/* ---- the scene's layers ---------------------------------------------------------------------- */

/* The cloud layer the column is for, or -1: the one on the ground that holds the observer with a
 * visibility of FOG_TABLE_MAX_VISIBILITY_M or less (fog), else the lowest whose top is above the
 * observer (who is below or inside it) of optical depth min_tau or more, else the highest layer of
 * FOG_TABLE_MIN_TAU or more below the observer (docs/decisions/2026-12-07-above-deck.md): the column
 * holds the observer's level wherever it is, its views down the upward radiance there. */
static int column_cloud_from(const fog_scene *s, double min_tau)
{
    int lowest = -1, below = -1;
    for (int i = 0; i < s->layer_count; i++) {
        const double base = s->layer[i].base_m, h = s->layer[i].thickness_m, tau = s->layer[i].tau550;
        if (!(h > 0.0))
            continue;
        if (s->altitude_m >= base + h) {
            if (tau >= FOG_TABLE_MIN_TAU && (below < 0 || base > s->layer[below].base_m))
                below = i;
            continue;
        }
        if (base <= 0.0)
            return tau / h >= 3.912 / FOG_TABLE_MAX_VISIBILITY_M ? i : -1;
        if (tau >= min_tau && (lowest < 0 || base < s->layer[lowest].base_m))
            lowest = i;
    }
    return lowest >= 0 ? lowest : below;
}

/* Whether every cloud layer but `cloud` is thin (below FOG_TABLE_MIN_TAU) and lies above its top: the
 * sky without it (fog_incident.h), which lights the column lit from above, holds them (cirrostratus
 * over an altostratus deck; docs/decisions/2026-12-07-two-layers-low-sun.md).  A thick layer above
 * (altostratus over stratocumulus) left that sky's paths 40 % dark at sun 2. */
static int thin_layers_above(const fog_scene *s, int cloud)
{
    const double top = s->layer[cloud].base_m + s->layer[cloud].thickness_m;
    for (int i = 0; i < s->layer_count; i++)
        if (i != cloud && (s->layer[i].base_m < top || s->layer[i].tau550 >= FOG_TABLE_MIN_TAU))
            return 0;
    return 1;
}

/* A single layer (the column's, `cloud`). */
static fog_layers one_layer(const fog_scene *s, int cloud)
{
    const fog_scene_layer *c = &s->layer[cloud];
    if (c->base_m <= 0.0 && s->altitude_m < c->base_m + c->thickness_m) /* fog around the observer */
        return c->tau550 >= FOG_TABLE_MIN_TAU       ? FOG_LAYERS_FOG
               : c->tau550 >= FOG_TABLE_MIN_TAU_FOG ? FOG_LAYERS_SHALLOW_FOG
                                                    : FOG_LAYERS_THIN_FOG;
    if (c->tau550 >= FOG_TABLE_MIN_TAU)
        return s->altitude_m >= c->base_m + c->thickness_m ? FOG_LAYERS_DECK_BELOW : FOG_LAYERS_DECK;
    if (c->ice && c->base_m > 0.0 && s->altitude_m < FOG_TABLE_ON_GROUND_M)
        return c->tau550 >= FOG_TABLE_THIN_LOW_SUN_MIN_TAU ? FOG_LAYERS_THIN_ICE : FOG_LAYERS_THIN_ICE_VEIL;
    return FOG_LAYERS_THIN;
}

fog_layers fog_scene_layers(const fog_scene *s, int *cloud)
{
    const int thick = column_cloud_from(s, FOG_TABLE_MIN_TAU);
    const int c = thick >= 0 ? thick : column_cloud_from(s, FOG_TABLE_MIN_TAU_THIN);
    *cloud = c;
    if (c < 0)
        return FOG_LAYERS_NONE;
    if (s->layer_count == 1)
        return one_layer(s, c);
    const fog_scene_layer *l = &s->layer[c];
    if (l->base_m <= 0.0 && s->altitude_m < l->thickness_m && l->tau550 >= FOG_TABLE_MIN_TAU_FOG &&
        l->tau550 < FOG_TABLE_MIN_TAU && thin_layers_above(s, c))
        return FOG_LAYERS_FOG_UNDER_THIN;
    if (thick >= 0 && l->base_m > 0.0 && thin_layers_above(s, c))
        return FOG_LAYERS_DECK_UNDER_THIN;
    return l->tau550 < FOG_TABLE_MIN_TAU ? FOG_LAYERS_THIN : FOG_LAYERS_MIXED;
}

/* ---- the regime ------------------------------------------------------------------------------ */

/* The sun (degrees) below which the column lit from above is the whole table; the blend ends
 * FOG_TABLE_BLEND_DEG above it. */
static double above_below_deg(const regime_bounds *b, const fog_scene *s, int cloud)
{
    return b->above_per_km ? fmax(b->above_below_deg, FOG_TABLE_MIN_SUN_DEG_PER_KM * s->layer[cloud].base_m / 1000.0)
                           : b->above_below_deg;
}

/* Whether the column lit from above takes the table at the scene's sun. */
static int lit_from_above(const regime_bounds *b, const fog_scene *s, int cloud)
{
    return b->above && s->fog_from_above && !s->under_deck && !s->reference && s->altitude_m < FOG_TABLE_ON_GROUND_M &&
           s->sun_z < sin((above_below_deg(b, s, cloud) + FOG_TABLE_BLEND_DEG) * FM_DEG) &&
           s->sun_z >= sin(b->above_from_deg * FM_DEG);
}

/* The lowest sun (degrees) of the day's column. */
static double day_min_deg(const regime_bounds *b, const fog_scene *s, int cloud)
{
    const int lit = b->day_min_lit_deg > 0.0 && s->fog_from_above && s->altitude_m < FOG_TABLE_ON_GROUND_M;
    const double min_sun = lit ? b->day_min_lit_deg : b->day_min_deg;
    return b->day_per_km ? fmax(min_sun, FOG_TABLE_MIN_SUN_DEG_PER_KM * s->layer[cloud].base_m / 1000.0) : min_sun;
}

fog_regime fog_scene_regime(const fog_scene *s)
{
    int cloud;
    const fog_layers layers = fog_scene_layers(s, &cloud);
    const regime_bounds *b = &table[layers];
    if (layers != FOG_LAYERS_NONE && lit_from_above(b, s, cloud))
        return s->layer[cloud].base_m > FOG_TABLE_FROM_ABOVE_MAX_BASE_M ? FOG_REGIME_FROM_ABOVE_SUNS
                                                                        : FOG_REGIME_FROM_ABOVE;
    if (layers == FOG_LAYERS_NONE || s->twilight || s->under_deck || s->reference ||
        s->sun_z < sin(day_min_deg(b, s, cloud) * FM_DEG))
        return FOG_REGIME_PATHS;
    if (b->day_suns_below_deg > 0.0 && s->sun_z < sin(b->day_suns_below_deg * FM_DEG))
        return b->day_suns;
    return FOG_REGIME_DAY;
}

double fog_scene_above_share(const fog_scene *s)
{
    int cloud;
    const fog_layers layers = fog_scene_layers(s, &cloud);
    if (layers == FOG_LAYERS_NONE)
        return 0.0;
    const double e = asin(clamp_cosine(s->sun_z)) / FM_DEG, below = above_below_deg(&table[layers], s, cloud);
    return e < below ? 1.0 : e > below + FOG_TABLE_BLEND_DEG ? 0.0 : (below + FOG_TABLE_BLEND_DEG - e) / FOG_TABLE_BLEND_DEG;
}

/* ---- from the job ---------------------------------------------------------------------------- */

/* The sky's layers, observer and sun (the job's flags cleared). */
static void sky_scene(const fm_sky *sky, fog_scene *s)
{
    *s = (fog_scene){.layer_count = sky->composition.cloud_count,
                     .altitude_m = v3_length(sky->observer) - sky->atm.bottom_radius_m,
                     .sun_z = sky->sun_dir.z};
    for (int i = 0; i < s->layer_count; i++) {
        const cloud_type *type = cloud_type_find(sky->composition.cloud[i].type);
        s->layer[i] = (fog_scene_layer){sky->composition.cloud[i].base_m, sky->composition.cloud[i].thickness_m,
                                        sky->composition.cloud[i].tau550, type && type->ice};
    }
}

void fog_scene_of(const render_job *job, fog_scene *s)
{
    sky_scene(job->sky, s);
    s->fog_from_above = job->fog_from_above;
    s->twilight = job->twilight != NULL;
    s->under_deck = job->under_deck != NULL;
    s->reference = job->params->quality == FM_QUALITY_REFERENCE;
}

fog_regime fog_regime_of(const render_job *job)
{
    fog_scene s;
    fog_scene_of(job, &s);
    return fog_scene_regime(&s);
}

int fog_regime_cloud(const fm_sky *sky)
{
    fog_scene s;
    int cloud;
    sky_scene(sky, &s);
    fog_scene_layers(&s, &cloud);
    return cloud;
}

double fog_regime_above_share(const fm_sky *sky)
{
    fog_scene s;
    sky_scene(sky, &s);
    return fog_scene_above_share(&s);
}

int fog_table_from_above(const render_job *job)
{
    const fog_regime r = fog_regime_of(job);
    return r == FOG_REGIME_FROM_ABOVE || r == FOG_REGIME_FROM_ABOVE_SUNS;
}

double fog_table_above_share(const render_job *job)
{
    return fog_table_from_above(job) ? fog_regime_above_share(job->sky) : 0.0;
}

int fog_table_local_sun(const render_job *job)
{
    return fog_regime_of(job) == FOG_REGIME_FROM_ABOVE_SUNS;
}

int fog_table_applies(const render_job *job)
{
    return fog_regime_of(job) != FOG_REGIME_PATHS;
}

int fog_table_sky(const fm_sky *sky)
{
    fog_scene s;
    sky_scene(sky, &s);
    if (column_cloud_from(&s, FOG_TABLE_MIN_TAU) < 0)
        return 0;
    /* a deck that the deck base takes (from DECK_MIN_SUN_DEG up) leaves the day's nodes to paths */
    for (int i = 0; i < sky->composition.cloud_count && sky->truncated; i++)
        if (sky->composition.cloud[i].tau550 >= SKY_TRUNCATE_TAU && sky->composition.cloud[i].base_m > s.altitude_m)
            return 0;
    return 1;
}

/* What a path estimator needs to know about the sky it traces: the atmosphere, the sun and its
 * tables, and which of the sampling techniques (path.h) are in use.  The tables are built above
 * the estimators (their builders run estimators) and read through their lookups below them. */
#ifndef FM_TRANSPORT_PATH_CONTEXT_H
#define FM_TRANSPORT_PATH_CONTEXT_H

#include "atmosphere/optical_depth.h"
#include "base/vec.h"
#include "atmosphere/sun_irradiance.h"

struct deck_base;
struct ground_irradiance;
struct shadow_flight_table;
struct sky_guide;

/* path_context.segment_sunlight: none; the segments that enter the Earth's umbra; every segment
 * (twilight); the umbra's and every rising one (a low sun behind thick haze: the sunlit air is above
 * the haze, which the paths reach by climbing). */
enum { SEGMENT_SUNLIGHT_NONE, SEGMENT_SUNLIGHT_UMBRA, SEGMENT_SUNLIGHT_ALL, SEGMENT_SUNLIGHT_RISING };

/* Deep twilight under a thin cloud layer: from its top this deep down (m) a vertex still sees the
 * sunlit band 2-5 degrees above the horizon toward the sun over the layer (a ray 3 degrees up
 * crosses an optical depth of 2.5 of cirrostratus from 300 m below its top), the light that the
 * phase function finds only by chance; the sky guide has levels in this band (twilight.c)
 * (docs/decisions/2026-12-07-cirrus-dusk-estimator.md, 2026-12-08-cirrus-band-guide.md). */
#define CLOUD_TOP_BAND_M 300.0

typedef struct path_context {
    const atmosphere *atm;
    const sun_disk *sun;
    const sun_irradiance *sun_table;
    const column_table *columns; /* species columns to the top (transmittance along segments) */
    const depth_table *mid_depth; /* the middle wavelength's optical depth to the top (shadow_flight.c) */
    vec3 sun_dir;       /* unit vector toward the sun's centre (Earth-centred frame) */
    int min_order, max_order;
    /* Fast path: paths whose first interaction is the ground are dropped (path_trace), because
     * single_scatter_radiance adds the ground's reflection of the tabulated diffuse irradiance. */
    int skip_ground_first;
    const struct ground_irradiance *ground_diffuse;
    /* Sun-guided directions: with probability sun_guide_fraction a scattering direction is drawn
     * from sun_guide (a forward-peaked phase function) about the sun's direction instead of from
     * the local phase function, combined by one-sample MIS.  The next vertex's sunlight is then
     * sampled where its aerosol forward peak makes it large. */
    const phase_function *sun_guide;
    double sun_guide_fraction;
    /* Which segments get their next interaction's sunlight by the expected value along the segment
     * (sunlit_segment.h) instead of the point estimate: SEGMENT_SUNLIGHT_*. */
    int segment_sunlight;
    /* Twilight: with probability sky_guide_fraction a direction is drawn from the sky guide
     * (sky_guide.h), toward the sunlit air; NULL when the sun is up. */
    const struct sky_guide *sky_guide;
    double sky_guide_fraction;
    /* The scattering coefficient (m^-1, at the hero wavelength) from which a vertex counts as in cloud,
     * where the guides take no share of the directions (path_direction.c) and no shadow flight starts
     * (path.c): FM_DENSE_SIGMA_PER_M, lower in a sky with a thinner cloud layer (sky_path.c); 0 reads
     * as FM_DENSE_SIGMA_PER_M (path_cloud_sigma). */
    double cloud_sigma_per_m;
    /* Deep twilight under a thin cloud layer (twilight.c): the layer's top (m from the Earth's
     * centre; 0 for none) where the sky guide has levels, and the guide's share of the directions
     * at a vertex within CLOUD_TOP_BAND_M of it (path_direction.c). */
    double cloud_top_radius_m;
    double cloud_top_guide_fraction;
    /* Deep twilight: segments place their next interaction by shadow_flight (shadow_flight.h)
     * instead of delta tracking; NULL otherwise. */
    const struct shadow_flight_table *shadow_flights;
    /* With shadow_flights: Russian roulette at each new vertex, not before the flight, each path's
     * survival raised by how much more light that vertex receives than its first point did
     * (shadow_flight_light against shadow_flight_light_and_ambient); see path.c. */
    int light_led_roulette;
    /* With shadow_flights: the share of a table node's first vertices placed along the view ray by
     * scattering x transmittance x the light there (view_ray_vertices.h); 0 by day. */
    double first_vertex_light_share;
    /* With shadow_flights: paths whose weight has grown far past 1 are split into copies that share
     * it (path.c); 0 leaves them whole. */
    int split_heavy_paths;
    /* With split_heavy_paths and the light-led roulette: the weight x lift past which a path splits
     * at a vertex (path.c); 0 for path.c's SPLIT_WEIGHT. */
    double vertex_split_weight;
    /* Under a deck (deck_base.h), for paths that start below its base: a segment that reaches the
     * base ends there and counts the light coming down from it (orders >= 3); no flight is forced
     * (none leaves the atmosphere).  NULL otherwise. */
    const struct deck_base *deck;
    /* Shared walks: with suns > 0 one walk serves the suns sun_dirs[0..suns-1] (PATH_SUNS_MAX at
     * most), each vertex's sunlight counted for each into its own sums (path_trace_from_suns) and
     * the sun guide drawing about each with an equal share of sun_guide_fraction; 0: sun_dir alone.
     * The walk then must not depend on the sun: no deck, twilight sampling, nor segment sunlight but
     * SEGMENT_SUNLIGHT_RISING for the first sun (sun_dirs[0] == sun_dir; no max_order), whose light
     * along a rising segment replaces its point estimate at the segment's end, the others' kept. */
    int suns;
    const vec3 *sun_dirs;
} path_context;

#define PATH_SUNS_MAX 4

/* path_context.cloud_sigma_per_m, or FM_DENSE_SIGMA_PER_M where it is not set. */
static inline double path_cloud_sigma(const path_context *c)
{
    return c->cloud_sigma_per_m > 0.0 ? c->cloud_sigma_per_m : FM_DENSE_SIGMA_PER_M;
}

/* The suns a walk serves (path_context.suns) and the s-th of them. */
static inline int path_sun_count(const path_context *c) { return c->suns > 0 ? c->suns : 1; }
static inline vec3 path_sun(const path_context *c, int s) { return c->suns > 0 ? c->sun_dirs[s] : c->sun_dir; }

#endif

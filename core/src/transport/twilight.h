/* When and how the renderer changes its estimator at twilight.
 *
 * Below the horizon (the sun's centre under the observer's horizontal plane) the light of the sky
 * comes from sunlit air far off and high up, seen across the Earth's shadow.  Then every render
 * builds the sky guide (sky_guide.h), draws half the scattering directions from it and counts every
 * segment's sunlight along the segment (sunlit_segment.h); in deep twilight, with the sun more
 * than 4.5 degrees down (twilight.c), segments also place their next interaction toward the light
 * (shadow_flight.h).  All are unbiased changes of sampling;
 * by day neither is used (except the along-segment sunlight on the rare segments that enter the
 * Earth's umbra).  Day and night, the fast path places the first vertex of its table nodes' paths
 * by stratified sampling along the view ray (view_ray_vertices.h). */
#ifndef FM_TRANSPORT_TWILIGHT_H
#define FM_TRANSPORT_TWILIGHT_H

#include "transport/sky_path.h"
#include "transport/shadow_flight.h"
#include "transport/shadow_flight_build.h"
#include "transport/sky_guide.h"

typedef struct twilight_sampling {
    sky_guide guide;
    int deep;  /* the flights below are in use */
    int split; /* heavy paths split (deep twilight above night, twilight.c) */
    double vertex_split_weight; /* path_context.vertex_split_weight: 0 unless the quality sets it */
    double cloud_top_radius; /* path_context.cloud_top_radius_m: deep twilight under a thin layer, else 0 */
    shadow_flight_table flights;
} twilight_sampling;

/* Whether a sun this far below the observer's horizontal plane (its elevation, degrees) is in deep
 * twilight, where the guided flights are used. */
int twilight_deep(double sun_elevation_deg);

/* *out: the sampling for a sky whose sun is below the horizon (malloc'ed, free() it); NULL by day
 * and for a black sky.  guide_offsets: in deep twilight, the sky guide's levels toward the sun
 * (sky_guide.h; 1 = none, as at preview quality, where their 0.5 s of tables would be a third of
 * the render).  shared: the flights' light already built for a lower sun (shadow_flight_build.h), or
 * NULL.  FM_ERR_OUT_OF_MEMORY, FM_ERR_CANCELLED (*cancel set) or FM_ERR_INTERNAL, *out NULL;
 * else FM_OK. */
fm_status twilight_sampling_create(const fm_sky *sky, int guide_offsets, const shadow_flight_columns *shared,
                                   int threads, const atomic_int *cancel, twilight_sampling **out);

/* sky_path_context (sky_path.h) with, when tw is not NULL, the twilight sampling. */
path_context twilight_path_context(const fm_sky *sky, const twilight_sampling *tw, int min_order, int max_order);

/* twilight_path_context over the media the fast path's multiple scattering traces
 * (sky_scattering_media, sky.h), with this sky's sun: a truncated copy keeps the sun it was built
 * with (fm_sky_set_sun and live.c's copies move only the sky's own). */
path_context scattering_path_context(const fm_sky *sky, const twilight_sampling *tw, int min_order, int max_order);

#define NODE_BATCHES 16

/* What the standard errors of a node's estimate need: the sum over its paths of the squared
 * luminance (CIE Y, or the one value of a monochromatic sky), and, for colour skies, the sums of
 * CIE X, Y, Z over each of NODE_BATCHES batches of consecutive paths (0 for monochromatic skies). */
typedef struct node_moments {
    double yy;
    double batch_xyz[NODE_BATCHES][3];
} node_moments;

/* A node's light parted by order (render.c fits the parts apart by day): `later` (K values) the sum
 * of the paths' orders 3 and up, yy[0] and yy[1] the sums over the paths of the squared luminance
 * of their order 2 and of their orders 3 and up. */
typedef struct node_orders {
    double *later;
    double yy[2];
} node_orders;

/* The fast path's estimate of orders >= 2 toward d at one table node, by day and at twilight: adds
 * the sum of `paths` path estimates (K values) to L, their first vertices stratified along the view
 * ray (view_ray_vertices.h) and, with twilight sampling (pc carries a guide), the guide's directions
 * after them.  m, if not NULL, receives their moments, for standard errors; shape, if not NULL,
 * the view ray's light_integral (view_ray_vertices.h: > 0 in deep twilight, else 0); orders, if not
 * NULL, the same light parted by order (L still gets all of it). */
void table_node_paths(const fm_sky *sky, const path_context *pc, vec3 d, int paths, uint64_t seed,
                      uint64_t item, int offset, double *L, node_moments *m, double *shape, node_orders *orders);

/* Where table_node_paths_suns puts one sun's light of a node: L as table_node_paths' L, m and
 * orders as its m and orders (each may be NULL; orders is given for every sun or for none). */
typedef struct node_sums {
    double *L;
    node_moments *m;
    node_orders *orders;
} node_sums;

/* table_node_paths for every sun of a walk shared by several (path_context.suns): sun s's light
 * into out[s]. */
void table_node_paths_suns(const fm_sky *sky, const path_context *pc, vec3 d, int paths, uint64_t seed,
                           uint64_t item, int offset, const node_sums *out, double *shape);

/* The node's ratio of means X / Y (c = 0) or Z / Y (c = 2) and its variance by the jackknife over
 * the batches (deleting one at a time); NAN for both when a batch's deletion leaves no light. */
void node_moments_ratio(const node_moments *m, int c, double *ratio, double *var);

#endif

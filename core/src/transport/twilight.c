#include "transport/twilight.h"

#include "base/rng.h"
#include "base/units.h"
#include "spectrum/spectral.h"
#include "transport/deck_base.h"
#include "transport/path.h"
#include "transport/shadow_flight_build.h"
#include "transport/sky_guide_build.h"
#include "transport/view_ray_vertices.h"

#include <math.h>
#include <stdlib.h>

/* Half the directions from the sky guide (docs/decisions/2026-12-06-twilight-thresholds.md). */
#define SKY_GUIDE_FRACTION 0.5

/* Deep twilight's sampling (guided flights, shadow_flight.h; the sky guide's levels toward the sun
 * and its light of order 2; the light-led roulette, heavy paths split, the first vertices led by
 * the light, the fit through the shape) from this sun elevation down: above it the flights cost
 * more time than they save (docs/decisions/2026-12-06-twilight-thresholds.md). */
#define DEEP_TWILIGHT_DEG -4.5

/* In deep twilight half the first vertices follow the light along the view ray
 * (view_ray_vertices.h): paths that start higher, in thinner air, are shorter, and the maps as
 * noisy (docs/decisions/2026-12-06-twilight-thresholds.md). */
#define FIRST_VERTEX_LIGHT_SHARE 0.5

/* From this sun elevation down heavy paths are not split (path.c).  There the air near the observer
 * lies deep in the Earth's shadow, the light at a path's first point is tiny, and the roulette's
 * lift passes the split weight at nearly every vertex; as copies inherit what is left of the
 * budget, the copies multiply with the depth of the sun, for a sky darker than starlight by five
 * decades (docs/decisions/2026-12-06-night-paths.md). */
#define SPLIT_UNTIL_DEG -21.0

/* Deep twilight under a thin cloud layer: the sky guide's share of the directions at a vertex in the
 * layer's upper part (CLOUD_TOP_BAND_M, path_direction.c), toward the sunlit band seen over its top;
 * one level lies this far above the top (m), above the layer's edge node (cloud_layer.c) where the
 * air is clear, for the air's vertices above it, and CLOUD_TOP_INSIDE_LEVELS more at the middles of
 * as many slices of the band, each seeing the band through the layer's air above it
 * (docs/decisions/2026-12-07-cirrus-dusk-estimator.md, 2026-12-08-cirrus-band-guide.md). */
#define CLOUD_TOP_GUIDE_FRACTION 0.25
#define CLOUD_TOP_LEVEL_M 100.0
#define CLOUD_TOP_INSIDE_LEVELS 3
_Static_assert(CLOUD_TOP_INSIDE_LEVELS + 1 <= SKY_GUIDE_EXTRA_LEVELS, "the sky guide's room for levels");

/* The top (m from the Earth's centre) of the highest thin cloud layer, one whose mean extinction at
 * 550 nm (sky_cloud_sigma550_per_m) is below FM_DENSE_SIGMA_PER_M, or 0 for none. */
static double thin_cloud_top(const fm_sky *sky)
{
    double top = 0.0;
    for (int i = 0; i < sky->composition.cloud_count; i++)
        if (sky_cloud_sigma550_per_m(sky, i) < FM_DENSE_SIGMA_PER_M)
            top = fmax(top, sky->atm.bottom_radius_m + sky->composition.cloud[i].base_m +
                                sky->composition.cloud[i].thickness_m);
    return top;
}

int twilight_deep(double sun_elevation_deg) { return sun_elevation_deg < DEEP_TWILIGHT_DEG; }

fm_status twilight_sampling_create(const fm_sky *sky, int guide_offsets, const shadow_flight_columns *shared,
                                   int threads, const atomic_int *cancel, twilight_sampling **out)
{
    *out = NULL;
    if (!(v3_dot(sky->sun_dir, sky->observer) < 0.0))
        return FM_OK;
    twilight_sampling *tw = malloc(sizeof *tw);
    if (!tw)
        return FM_ERR_OUT_OF_MEMORY;
    path_context single = sky_path_context(sky, 1, 1);
    double sun_elevation = asin(clamp_cosine(v3_dot(v3_normalize(sky->observer), sky->sun_dir)));
    tw->deep = twilight_deep(sun_elevation / FM_DEG);
    tw->split = tw->deep && sun_elevation > SPLIT_UNTIL_DEG * FM_DEG;
    tw->vertex_split_weight = 0.0;
    tw->cloud_top_radius = tw->deep ? thin_cloud_top(sky) : 0.0;
    int usable = 0, extras = 0;
    sky_guide_extra extra[SKY_GUIDE_EXTRA_LEVELS];
    if (tw->cloud_top_radius > 0.0) {
        extra[extras++] = (sky_guide_extra){tw->cloud_top_radius + CLOUD_TOP_LEVEL_M, 0};
        for (int j = 0; j < CLOUD_TOP_INSIDE_LEVELS; j++)
            extra[extras++] =
                (sky_guide_extra){tw->cloud_top_radius - (j + 0.5) * CLOUD_TOP_BAND_M / CLOUD_TOP_INSIDE_LEVELS, 1};
    }
    /* the flights' table first: in deep twilight the sky guide adds the light of order 2 from it */
    fm_status s = tw->deep ? shadow_flight_build(&tw->flights, &single, sky->observer, shared, threads, cancel) : FM_OK;
    if (!s)
        s = sky_guide_build(&tw->guide, &single, sky->observer, tw->deep ? guide_offsets : 1, threads,
                            tw->deep ? &tw->flights : NULL,
                            extra, extras, cancel, &usable);
    if (s || !usable) {
        free(tw); /* a black sky (deep night): nothing to guide toward */
        return s;
    }
    *out = tw;
    return FM_OK;
}

path_context twilight_path_context(const fm_sky *sky, const twilight_sampling *tw, int min_order, int max_order)
{
    path_context pc = sky_path_context(sky, min_order, max_order);
    if (tw) {
        pc.sky_guide = &tw->guide;
        pc.shadow_flights = tw->deep ? &tw->flights : NULL;
        pc.light_led_roulette = tw->deep;
        pc.split_heavy_paths = tw->split;
        pc.vertex_split_weight = tw->vertex_split_weight;
        pc.first_vertex_light_share = tw->deep ? FIRST_VERTEX_LIGHT_SHARE : 0.0;
        pc.sky_guide_fraction = SKY_GUIDE_FRACTION;
        pc.cloud_top_radius_m = tw->cloud_top_radius;
        pc.cloud_top_guide_fraction = tw->cloud_top_radius > 0.0 ? CLOUD_TOP_GUIDE_FRACTION : 0.0;
        /* every segment along its length: with guided directions of small weight, a point estimate
         * after Russian roulette would bring the noise back */
        pc.segment_sunlight = SEGMENT_SUNLIGHT_ALL;
    }
    return pc;
}

path_context scattering_path_context(const fm_sky *sky, const twilight_sampling *tw, int min_order, int max_order)
{
    path_context pc = twilight_path_context(sky_scattering_media(sky), tw, min_order, max_order);
    pc.sun_dir = sky->sun_dir;
    return pc;
}

/* Under a deck, the light coming down from its base where the view ray ends, through the air below
 * (orders >= 3): the same for every path, so it adds no noise. */
static void deck_light_through(const view_ray_vertices *v, const path_context *pc, double *L)
{
    double T[FM_MAX_WAVELENGTHS];
    atmosphere_transmittances(pc->atm, v->column[VIEW_RAY_CELLS], T);
    deck_base_radiance(pc->deck, v3_madd(v->seg.origin, v->seg.dir, v->seg.t_end), v->seg.dir, pc->sun_dir, 1.0, L);
    spectral_mul(L, T, pc->atm->grid.count);
}

/* One path's light into a node's sums (node_sums), as path p of `paths`: own holds all its orders,
 * or, when parted (out->orders), order 2 alone, and then later those above (own gets them). */
static void add_path(const fm_sky *sky, double *own, const double *later, const node_sums *out, int p, int paths)
{
    const int K = sky->atm.grid.count;
    if (out->orders) {
        double y2 = spectral_grid_luminance(&sky->atm.grid, own);
        double y3 = spectral_grid_luminance(&sky->atm.grid, later);
        out->orders->yy[0] += y2 * y2;
        out->orders->yy[1] += y3 * y3;
        spectral_add(out->orders->later, later, K);
        spectral_add(own, later, K);
    }
    spectral_add(out->L, own, K);
    if (out->m) {
        double xyz[3] = {0.0, own[0], 0.0}; /* Y: the luminance, or a monochromatic sky's value */
        if (sky->atm.grid.colour) {
            double *batch = out->m->batch_xyz[(int)((int64_t)p * NODE_BATCHES / paths)];
            spectral_grid_to_xyz(&sky->atm.grid, own, xyz);
            for (int c = 0; c < 3; c++)
                batch[c] += xyz[c];
        }
        out->m->yy += xyz[1] * xyz[1];
    }
}

void table_node_paths(const fm_sky *sky, const path_context *pc, vec3 d, int paths, uint64_t seed,
                      uint64_t item, int offset, double *L, node_moments *m, double *shape, node_orders *orders)
{
    const node_sums out = {L, m, orders};
    table_node_paths_suns(sky, pc, d, paths, seed, item, offset, &out, shape);
}

void table_node_paths_suns(const fm_sky *sky, const path_context *pc, vec3 d, int paths, uint64_t seed,
                           uint64_t item, int offset, const node_sums *out, double *shape)
{
    const int K = sky->atm.grid.count, S = path_sun_count(pc);
    /* First vertices stratified along the view ray (view_ray_vertices.h), by day too: less noise in
     * less time than delta tracking from the observer (docs/decisions/2026-12-06-twilight-thresholds.md). */
    view_ray_vertices v;
    if (shape)
        *shape = 0.0;
    if (!view_ray_vertices_init(&v, pc, sky->observer, d))
        return; /* no air along the ray */
    if (shape)
        *shape = v.light_integral;
    double deck[FM_MAX_WAVELENGTHS] = {0}; /* every path's share of the light from the deck's base */
    if (v.at_deck)
        deck_light_through(&v, pc, deck);
    sobol_scramble scramble;
    sobol_scramble_init(&scramble, rng_qmc_seed(seed, item), sobol_levels((uint64_t)paths));
    for (int p = 0; p < paths; p++) {
        rng r = rng_for_qmc(seed, item, (uint64_t)p, (uint64_t)paths);
        rng_use_scramble(&r, &scramble);
        double own[PATH_SUNS_MAX][FM_MAX_WAVELENGTHS], later[PATH_SUNS_MAX][FM_MAX_WAVELENGTHS];
        double *owns[PATH_SUNS_MAX], *laters[PATH_SUNS_MAX];
        for (int s = 0; s < S; s++) {
            spectral_fill(owns[s] = own[s], 0.0, K);
            spectral_fill(laters[s] = later[s], 0.0, K);
        }
        double weight[FM_MAX_WAVELENGTHS];
        vec3 x = view_ray_vertex(&v, pc, (p + rng_uniform(&r)) / paths, weight);
        path_trace_from_suns(pc, x, d, weight, (p + offset) % K, &r, owns, out->orders ? laters : NULL);
        for (int s = 0; s < S; s++) {
            if (v.at_deck)
                spectral_add(out[s].orders ? later[s] : own[s], deck, K);
            add_path(sky, own[s], later[s], &out[s], p, paths);
        }
    }
    sobol_scramble_free(&scramble);
}

void node_moments_ratio(const node_moments *m, int c, double *ratio, double *var)
{
    double total[3] = {0.0, 0.0, 0.0}, deleted[NODE_BATCHES], mean = 0.0;
    for (int b = 0; b < NODE_BATCHES; b++)
        for (int q = 0; q < 3; q++)
            total[q] += m->batch_xyz[b][q];
    *ratio = *var = NAN;
    for (int b = 0; b < NODE_BATCHES; b++) {
        double y = total[1] - m->batch_xyz[b][1];
        if (!(y > 0.0))
            return;
        deleted[b] = (total[c] - m->batch_xyz[b][c]) / y;
        mean += deleted[b] / NODE_BATCHES;
    }
    double sum2 = 0.0;
    for (int b = 0; b < NODE_BATCHES; b++)
        sum2 += (deleted[b] - mean) * (deleted[b] - mean);
    *ratio = total[c] / total[1];
    *var = sum2 * (NODE_BATCHES - 1.0) / NODE_BATCHES;
}

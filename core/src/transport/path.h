/* The reference estimator: spectral volumetric path tracing from the observer.
 *
 * Every path carries all K wavelengths of the spectral grid.  One of them, the hero, drives the
 * random decisions (free flights by delta tracking, scatter / absorb / null events, choice of
 * scattering species and direction); the others are weighted by one-sample spectral MIS with the
 * balance heuristic over all K hero choices (the path pdf of wavelength k relative to the hero's is
 * carried in q[k]), so a strongly wavelength-dependent medium gives no colour noise.
 *
 * At every scattering vertex and at the ground, next-event estimation adds direct sunlight from the
 * precomputed disk-integrated transmittance table (sun_irradiance.h); directions sampled by the phase
 * function never count the sun, so it is never counted twice.  Ground: Lambertian, bounced with
 * cosine sampling and, while the sun is 10 degrees or more above the ground's horizon, the sun guide
 * below (one-sample MIS).  Russian roulette ends paths: every order of scattering is included.  It
 * plays once the light found by the last direction is counted: before the next flight when the
 * segment's sunlight was counted along it, else at the next vertex after its point estimate (a
 * sun-guided direction's small weight pays off there).
 * Scattering directions are drawn from the local phase function or, a fraction of the time, from an
 * aerosol phase function about the sun (the sun guide, one-sample MIS), so the next vertex's direct
 * sunlight through its aerosol forward peak is not left to chance.  Segments that would leave the
 * atmosphere are optionally forced to collide (weight 1 - exp(-majorant depth)), which keeps
 * thin-air paths useful without bias.  A segment that enters
 * the Earth's umbra (every segment, at twilight) gets its next interaction's sunlight as the
 * expected value along it (sunlit_segment.h) and no point estimate at that interaction; Russian
 * roulette plays after that.  At twilight a third direction technique, the sky guide
 * (sky_guide.h), joins the MIS; in deep twilight the next interaction along a segment is placed
 * toward the light instead of by delta tracking (shadow_flight.h), the roulette spares the paths
 * that have reached brighter air than they started in, and a path whose weight has grown heavy is
 * split into copies that share it.
 *
 * Orders: the order of a contribution is the number of interactions (air scattering or ground
 * reflection) on the path, including the vertex where the sun is connected.  Contributions outside
 * [min_order, max_order] are not counted (max_order 0 = unlimited): order 1 is single scattering. */
#ifndef FM_TRANSPORT_PATH_H
#define FM_TRANSPORT_PATH_H

#include "atmosphere/optical_depth.h"
#include "atmosphere/sun_irradiance.h"
#include "base/rng.h"
#include "base/vec.h"

struct ground_irradiance;
struct sky_guide;

/* path_context.segment_sunlight: none; the segments that enter the Earth's umbra; every segment
 * (twilight); the umbra's and every rising one (a low sun behind thick haze: the sunlit air is above
 * the haze, which the paths reach by climbing). */
enum { SEGMENT_SUNLIGHT_NONE, SEGMENT_SUNLIGHT_UMBRA, SEGMENT_SUNLIGHT_ALL, SEGMENT_SUNLIGHT_RISING };

typedef struct path_context {
    const atmosphere *atm;
    const sun_disk *sun;
    const sun_irradiance *sun_table;
    const column_table *columns; /* species columns to the top (transmittance along segments) */
    const depth_table *mid_depth; /* the middle wavelength's optical depth to the top (shadow_flight.c) */
    vec3 sun_dir;       /* unit vector toward the sun's centre (Earth-centred frame) */
    int min_order, max_order;
    int force_escapes;  /* force collisions on segments that would leave through the top */
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
} path_context;

/* Adds one path's radiance estimate (W m^-2 sr^-1 nm^-1, per grid wavelength) to L. */
void path_trace(const path_context *ctx, vec3 origin, vec3 dir, int hero, rng *r, double *L);

/* The same for a path that begins with a scattering at x (arrived along dir, counted as order 1)
 * with spectral weights weight[k] (the caller's f/p of placing the vertex there).  L_later, if not
 * NULL, receives the contributions of orders 3 and up instead of L (the same path, its light
 * parted by order). */
void path_trace_from(const path_context *ctx, vec3 x, vec3 dir, const double *weight, int hero, rng *r, double *L,
                     double *L_later);

/* Mixture phase function sigma_s-weighted over species at densities n: fills p[k] for every grid
 * wavelength (returns the scattering coefficients in sigma_s[k]). */
void medium_phase(const atmosphere *atm, const double *n, double cos_theta, double *p, double *sigma_s);

#endif

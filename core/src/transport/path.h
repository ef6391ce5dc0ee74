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
 * atmosphere are forced to collide (weight 1 - exp(-majorant depth)), which keeps thin-air paths
 * useful without bias.  A segment that enters
 * the Earth's umbra (every segment, at twilight) gets its next interaction's sunlight as the
 * expected value along it (sunlit_segment.h) and no point estimate at that interaction; Russian
 * roulette plays after that.  At twilight a third direction technique, the sky guide
 * (sky_guide.h), joins the MIS; in deep twilight the next interaction along a segment is placed
 * toward the light instead of by delta tracking (shadow_flight.h), the roulette spares the paths
 * that have reached brighter air than they started in, and a path whose weight has grown heavy is
 * split into copies that share it.  Under a deck (path_context.deck) a segment that reaches the
 * deck's base ends there with the base's light (deck_base.h).
 *
 * The code (path.c) follows the structure of a volumetric path tracer such as pbrt-v4's: a path
 * state (spectral weights, order, the stage it goes on from); one free-flight routine that places
 * tentative collisions (delta tracking, its first collision forced on segments that leave through
 * the top, or deep twilight's shadow flights) and calls back at each to decide scattering or a null
 * event; vertex handlers for a scattering in the air and a reflection at the ground (a path that
 * leaves through the top ends: space is black); and an explicit stack for the copies of split
 * paths, run last in first out, so in the order of a recursion and with its random numbers.
 *
 * Orders: the order of a contribution is the number of interactions (air scattering or ground
 * reflection) on the path, including the vertex where the sun is connected.  Contributions outside
 * [min_order, max_order] are not counted (max_order 0 = unlimited): order 1 is single scattering. */
#ifndef FM_TRANSPORT_PATH_H
#define FM_TRANSPORT_PATH_H

#include "base/rng.h"
#include "transport/path_context.h"

/* Adds one path's radiance estimate (W m^-2 sr^-1 nm^-1, per grid wavelength) to L; returns the
 * copies that it and its copies split into, together (0 unless heavy paths split; at most 1024). */
int path_trace(const path_context *ctx, vec3 origin, vec3 dir, int hero, rng *r, double *L);

/* The same for a path that begins with a scattering at x (arrived along dir, counted as order 1)
 * with spectral weights weight[k] (the caller's f/p of placing the vertex there).  L_later, if not
 * NULL, receives the contributions of orders 3 and up instead of L (the same path, its light
 * parted by order). */
int path_trace_from(const path_context *ctx, vec3 x, vec3 dir, const double *weight, int hero, rng *r, double *L,
                    double *L_later);

/* path_trace_from for a walk shared by the suns of ctx (path_context.suns): sun s's light goes to
 * L[s] and, if L_later is not NULL, its orders 3 and up to L_later[s]. */
int path_trace_from_suns(const path_context *ctx, vec3 x, vec3 dir, const double *weight, int hero, rng *r,
                         double *const *L, double *const *L_later);

#endif

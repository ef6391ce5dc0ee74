/* Building the sky guide (sky_guide.h) from single-scattering quadrature (single_scatter.h) and, in
 * deep twilight, the flights' light of order 2 (shadow_flight.h). */
#ifndef FM_TRANSPORT_SKY_GUIDE_BUILD_H
#define FM_TRANSPORT_SKY_GUIDE_BUILD_H

#include "transport/path_context.h"
#include "transport/shadow_flight.h"
#include "transport/sky_guide.h"

#include <stdatomic.h>

/* One more level: its radius (m from the Earth's centre), and whether its sky is single scattering
 * alone even with flights.  Inside a thin layer the flights' light of order 2 (isotropic, and
 * tabulated kilometres apart) is the layer's own diffuse glow over most of the sky, while the
 * light that a vertex's next segment counts is the band's single scattering: the guide aims at
 * that (docs/decisions/2026-12-08-cirrus-band-guide.md). */
typedef struct sky_guide_extra {
    double radius;
    int single_only;
} sky_guide_extra;

/* Builds the guide from single_scatter_radiance with `single` at altitudes above `observer` (its
 * own altitude first) on `threads` threads; with offsets > 1 (at most SKY_GUIDE_MAX_OFFSETS), also
 * at those altitudes 2, 4, 6, 9 and 12 degrees of arc toward the sun, whose local sun stands that
 * much higher (deep twilight: the vertices that matter are there).  With flights (deep twilight),
 * the light of order 2 from shadow_flight_order2 is added; NULL leaves it out.  A vertex uses the offset whose
 * local sun is nearest its own, then the altitude nearest its own among that offset's levels that
 * see light (a black level is left out).  *usable: 0 when every level is black (the guide is then
 * unusable), else 1.  extra (`extras` of them, at most SKY_GUIDE_EXTRA_LEVELS): more levels per
 * offset, at and just below a thin cloud layer's top, whose skies are the sunlit band that the
 * layer's upper vertices see over it, through the layer's air above them (path_direction.c); a
 * level with single_only leaves the light of order 2 out (sky_guide_extra).
 * FM_ERR_OUT_OF_MEMORY, FM_ERR_CANCELLED (*cancel set) or FM_ERR_INTERNAL (its threads could not
 * run), else FM_OK. */
fm_status sky_guide_build(sky_guide *g, const path_context *single, vec3 observer, int offsets, int threads,
                          const shadow_flight_table *flights, const sky_guide_extra *extra, int extras,
                          const atomic_int *cancel, int *usable);

#endif

/* An elevated cloud deck at a low sun and in twilight: each view lit by the sun where it meets the
 * deck (docs/decisions/2026-12-07-deck-local-sun.md).
 *
 * The plane column lights the whole deck with the observer's sun, but a view at elevation e meets a
 * base at h over an arc theta = acos(R cos e / (R + h)) - e away, where the sun stands theta cos(phi)
 * higher (phi the view's azimuth from the sun's): at the horizon under a base at 3 km, 1.76 degrees.
 * In twilight the sky above the deck brightens by some 0.5 % per 0.01 degree of sun, so one sun for
 * the whole deck puts 10 % errors 10 degrees up and factors at the horizon.  The column's table is
 * made at FOG_LOCAL_SUNS suns (the observer's and that arc at the horizon either side of it) and each
 * sky node takes the light along its view: the air's (weighted by what it scatters, seen through
 * the air before it) and the deck's base (seen through all of it), each at its own sun, from the
 * tables interpolated quadratically in the logarithm over the sun's elevation. */
#ifndef FM_RENDER_FOG_LOCAL_SUN_H
#define FM_RENDER_FOG_LOCAL_SUN_H

#include "atmosphere/atmosphere.h"
#include "transport/sky_grid.h"

#define FOG_LOCAL_SUNS 3

/* The arc (rad) from the observer on the ground to where a horizontal view meets a base at base_m:
 * the sun's largest shift over the deck's visible part, and the spacing of the suns. */
double fog_local_sun_span(const atmosphere *atm, double base_m);

/* Under a thin layer of ice the arcs toward the sun's azimuth count this many times, falling to once
 * away from it ((1 + cos phi) / 2 between).  The air under the layer scatters toward the observer the
 * layer's forward glow, which comes from farther along than the air itself: the true arcs are too
 * short and the layer's own arc too long.  An effective scale fitted to the reference, not derived
 * (docs/decisions/2026-12-07-thin-layers-low-sun.md). */
#define FOG_LOCAL_SUN_THIN_TOWARD 2.0

/* The table's sums at every node from the tables at[j] ([node][K] each, made at the observer's sun
 * plus (j - 1) span), the deck's base at base_m, each point's shift from the observer's sun times
 * `shift` (0 to 1) and toward the sun's azimuth `toward` times (1 for a deck), each point's view
 * tilted by `tilt` (0 to 1) times the arc (1: its elevation over the point's horizon; 0 for a
 * deck): into out ([node][K]); shifts beyond span take the nearest table.  The ground rows (looking down) take the
 * observer's sun. */
void fog_local_sun_combine(const atmosphere *atm, const sky_grid *grid, double base_m, double span, double shift,
                           double toward, double tilt, const double *const at[FOG_LOCAL_SUNS], double *out);

/* Above a deck: the sky rows take the observer's sun (at[1]), each ground row the sun where its view
 * meets the deck's top at top_m (the observer at observer_m above the ground), shifted from the
 * observer's by the arc times `shift` (0 to 1), from the tables at[j] made at the observer's sun plus
 * (j - 1) span; shifts beyond span take the nearest. */
void fog_local_sun_combine_down(const atmosphere *atm, const sky_grid *grid, double observer_m, double top_m,
                                double span, double shift, const double *const at[FOG_LOCAL_SUNS], double *out);

#endif

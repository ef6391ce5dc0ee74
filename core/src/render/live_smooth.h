/* The live sky's day nodes' multiple-scattering tables smoothed across the sun elevation: each
 * node's noise is its own (live.c gives the day nodes independent seeds), while the sky by day
 * changes slowly with the sun, so a local quadratic in the node index through each value's
 * logarithm over the neighbouring nodes averages the noise and keeps the trend
 * (docs/decisions/2026-12-06-live-day-nodes.md). */
#ifndef FM_RENDER_LIVE_SMOOTH_H
#define FM_RENDER_LIVE_SMOOTH_H

#include "render/live_tables.h"

/* Nodes on either side of a smoothed node that its value takes in. */
#define LIVE_SMOOTH_HALF 2

/* The weights h[0..n-1] (summing to 1) that give the value at x = 0 of the least-squares quadratic
 * through the values at x[0..n-1] weighted by w[0..n-1]: exact for any quadratic.  Returns 0 when
 * the points do not determine a quadratic (fewer than 3 distinct x with weight), leaving h alone. */
int live_quadratic_weights(const double *x, const double *w, int n, double *h);

/* Smooths the multiple-scattering tables of the nodes fresh[i] != 0 at or above from_deg, each from
 * the fresh nodes at or above from_deg within LIVE_SMOOTH_HALF of it, as they were before any was
 * smoothed; a value with a non-positive neighbour stays as it was.  Returns FM_ERR_OUT_OF_MEMORY or
 * FM_OK. */
fm_status live_smooth_day(fm_sky_live *live, const unsigned char *fresh, double from_deg);

/* Deep twilight (twilight.h): its nodes' tables, fitted from a quarter of the preview's paths,
 * keep a noise of several percent spread over the sky by the fit's few terms.  Each value of a
 * fresh deep twilight node is replaced by the least-squares quadratic in the sun elevation through
 * the logarithms of that value at every fresh node up to LIVE_SMOOTH_DEEP_WITH_DEG, weighted by a
 * Gaussian in the elevation (the sky falls by decades there, smoothly, and its nodes are 2 to 2.5
 * degrees apart).  The nodes above deep twilight take part unchanged: their noise is their own
 * (another seed, another estimator of the same light), and with them the highest deep node lies
 * inside the window, not at its end, where a quadratic's value keeps nearly all of its own noise.
 * The Gaussian's width is the one of LIVE_SMOOTH_DEEP_WIDTHS (degrees) that predicts each inner
 * deep node's logarithms best from the other nodes (leave-one-out): the widest averages the most
 * noise (hazy skies), while a clear sky's logarithm, far less noisy, bends more than a quadratic
 * over all the nodes follows (its slope is least near sun -9).  Every channel of a value is scaled
 * alike (the node's colour stays); a value that is not positive at one of the nodes, or fewer than
 * LIVE_SMOOTH_DEEP_MIN such nodes, leave it as it was.  Returns FM_ERR_OUT_OF_MEMORY or FM_OK. */
#define LIVE_SMOOTH_DEEP_WIDTHS {2.0, 3.0, 5.0}
#define LIVE_SMOOTH_DEEP_WITH_DEG -3.0
#define LIVE_SMOOTH_DEEP_MIN 4
fm_status live_smooth_deep_twilight(fm_sky_live *live, const unsigned char *fresh);

#endif

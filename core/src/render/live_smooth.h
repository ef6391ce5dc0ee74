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
 * keep a noise of several percent spread over the sky by the fit's few terms.  The logarithm of the
 * luminance of each fresh deep twilight node's table is smoothed across the sun elevation, through
 * every fresh node up to LIVE_SMOOTH_DEEP_WITH_DEG (the sky falls by decades there, smoothly, and its
 * nodes are 2 to 2.5 degrees apart), term by term of its cosine series over the view direction: per
 * domain (the sky's rows, the ground's), a DCT-I over the columns (relative azimuth 0 to pi) and then
 * over the rows.  Each term is replaced by a weighted least-squares polynomial in the sun elevation
 * through that term at the nodes, weighted by a Gaussian in the elevation: one of LIVE_SMOOTH_DEEP_FITS
 * ({degree, width in degrees}), chosen per class of terms (the two first-order terms, the rest) as
 * the one that predicts each inner deep node's terms best from the other nodes (leave-one-out).  The
 * sky's shape about its level changes slowly with the sun and holds most of a node's noise in its
 * many higher terms: a wide mean or line across the nodes takes most of that noise, at the lowest
 * node too, where a quadratic's value keeps nearly all of its own.  The level (the mean over the
 * domain, the least noisy term) is each node's own: it falls by decades and bends, which no fit of
 * LIVE_SMOOTH_DEEP_FITS follows within a percent.  The logarithms of each node are then raised by half the mean
 * square of what the smoothing took off them (a mean of logarithms of noisy values lies half their
 * relative variance below the logarithm of their mean).  The colour (ln X/Y and ln Z/Y, where every
 * channel is positive) has its rest smoothed by the rest's fit, its level and first-order terms the
 * node's own.  The nodes above deep twilight take part unchanged: their noise is their own (another
 * seed, another estimator of the same light); but their shape over the sky is off the deep nodes'
 * curve, and they take no part in the rest's fit but at the band's edge (the highest deep node).  A
 * domain with a value that is not positive at one of the nodes is smoothed value by value (each
 * value lit at every node by the fit chosen over them, its luminance, every channel scaled alike;
 * the others stay), and fewer than LIVE_SMOOTH_DEEP_MIN nodes leave the tables as they were
 * (docs/decisions/2026-12-07-live-deep-denoise.md, 2026-12-07-live-minus6.md,
 * 2026-12-07-live-deep-variance.md, 2026-12-07-live-smooth-bias.md).  Returns
 * FM_ERR_OUT_OF_MEMORY or FM_OK. */
#define LIVE_SMOOTH_DEEP_FITS                                                                                   \
    {{2, 2.0}, {2, 3.0}, {2, 5.0}, {1, 5.0}, {1, 10.0}, {1, 20.0}, {0, 5.0}, {0, 10.0}, {0, 20.0}}
#define LIVE_SMOOTH_DEEP_WITH_DEG -3.0
#define LIVE_SMOOTH_DEEP_MIN 4
fm_status live_smooth_deep_twilight(fm_sky_live *live, const unsigned char *fresh);

#endif

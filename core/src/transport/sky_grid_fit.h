/* Smoothing the multiple-scattering table: a penalised least-squares fit that averages the noise of
 * many nodes.
 *
 * The table's nodes (sky_grid.h) are independent Monte Carlo estimates of a radiance that is smooth
 * over each domain (sky, ground): a few significant cosines of the relative azimuth, slow change
 * with the row coordinate u, while each node carries several percent of relative noise.  Per
 * domain, the fit is
 *     L(u, phi) = sum_{m <= M} cos(m phi) f_m(u),
 * each f_m a penalised smoother over the rows (a P-spline of the rows' own coefficients: weighted
 * squared error plus lambda_m times the summed squared third differences between rows; for m >= 1
 * f_m = (1 - u) g_m, since at the pole, u = 1, every column is the same direction).  The columns
 * are weighted by the trapezoid rule, which makes the cosines orthogonal on the uniform columns (a
 * DCT-I per row, then one smoother over the rows per cosine), and the rows by 1 / (their mean
 * luminance)^2, so that the error minimised is relative.
 *
 * Coarse aerosols (desert dust) give multiple scattering an aureole no such basis holds (at sun 30,
 * 5 times its row's mean at the sun, half that one column away), so three more terms may join it:
 * exp(-gamma / w) of the angle gamma from the sun, w = 3, 8 and 20 degrees, as a partially linear
 * model (Speckman's estimate: the terms' coefficients from their part the smoothers miss).
 *
 * M, every lambda_m (25 values, half a decade apart) and the aureole terms are chosen per domain
 * by Stein's unbiased risk estimate (SURE): from the nodes' own variances it estimates each
 * candidate's expected squared error against the unknown truth, bias included, and the raw nodes
 * (risk: their variance) stay when no fit is expected to do better.  The risk is a sum over the
 * cosines, so each lambda_m is chosen on its own; with the aureole terms the smoothers are chosen
 * again for the nodes less the terms' part (three rounds).  The fit is linear in the nodes, so it
 * adds no bias beyond what the smoothers cannot represent, which SURE counts.  Rows whose fitted
 * luminance falls below 0.15 of their own mean somewhere (deep twilight's horizon) keep their raw
 * nodes: the row weights would leave those dim nodes a large relative error.
 *
 * In deep twilight a shape per node may be given (table_node_paths: the light of orders 1 and 2
 * along the node's view ray, scattered isotropically toward the observer).  The sky's nodes are then
 * fitted divided by it, and the fit multiplied back: the ratio varies far less within a row than
 * the nodes do, so every row passes the range check and the fit averages many more nodes.  The rows
 * within 1.5 degrees of the horizon are fitted through the shape as a band of their own, across the
 * azimuth only (a row's cosines kept as they are, only the highest dropped): the ratio doubles there
 * (the shape leaves out the higher orders, which weigh most in the dense air that those rays alone
 * cross), and fitting through that knee would bias the rows above.
 * The figures behind these choices: docs/decisions/2026-12-06-sky-grid-fit.md */
#ifndef FM_TRANSPORT_SKY_GRID_FIT_H
#define FM_TRANSPORT_SKY_GRID_FIT_H

#include "transport/sky_grid.h"

/* The choice for one domain: the highest cosine kept and the number of aureole terms (0 or 3), or
 * azimuth_modes = -1 when the raw nodes were kept (rows failing the range check keep theirs even
 * when a fit was chosen); risk_raw and risk_fit: the estimated relative squared errors summed over
 * the domain's nodes. */
typedef struct sky_grid_fit_choice {
    int azimuth_modes, aureole_terms;
    double risk_raw, risk_fit;
} sky_grid_fit_choice;

/* Replaces each domain's values (every channel) by the fit chosen from y and var_y: per node
 * (row-major, sky rows first) the luminance estimate and its variance; sun_elevation (rad) places
 * the aureole terms (the relative azimuth 0 is the sun's).  shape, if not NULL and positive at
 * every sky node, is the sky's shape (above); otherwise it is left out.  Values are kept >= 0.
 * choice, if not NULL, receives the sky's [0] (with a shape, that of the rows above the horizon's
 * band) and the ground's [1] choice.  A grid beyond 64 rows per domain or 64 columns keeps its nodes.
 * Returns FM_OK or FM_ERR_OUT_OF_MEMORY. */
fm_status sky_grid_fit(sky_grid *g, double sun_elevation, const double *y, const double *var_y,
                       const double *shape, sky_grid_fit_choice choice[2]);

/* Colour at twilight.  A colour table (3 channels, CIE XYZ) fitted by sky_grid_fit keeps its Y; X
 * and Z become Y times a fit of the nodes' own ratios X / Y and Z / Y (ratio[0], ratio[1], per
 * node, with their variances), each chosen as above, for the horizon's band (above), the sky
 * above it and the ground separately.  One fit for X, Y and Z averages the colour as little as the
 * luminance, while the ratios vary more slowly and are less noisy, since a path's X, Y and Z move
 * together; a twilight map's R = 3.24 X - 1.54 Y - 0.50 Z, a small difference of large terms, needs
 * that.  The ratios' variances come from the jackknife over batches of a node's paths (the delta
 * method's first order underestimates them, which would let the fit keep every cosine).  A node's
 * ratio of means is biased by its covariance with Y, far below its noise.  Nodes with a ratio that
 * is not finite leave their domain raw. */
fm_status sky_grid_fit_chroma(sky_grid *g, double sun_elevation, const double *const ratio[2],
                              const double *const ratio_var[2]);

#endif

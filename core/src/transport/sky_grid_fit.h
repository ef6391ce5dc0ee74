/* Smoothing the multiple-scattering table: a penalised least-squares fit that averages the noise of
 * many nodes.
 *
 * The table's nodes (sky_grid.h) are independent Monte Carlo estimates of a radiance that is smooth
 * over each domain (sky, ground): at the urban sunset 20 x 16 sky nodes at 2048 paths each carry 8%
 * relative noise, while the function itself has only a few significant cosines of the relative
 * azimuth and varies slowly with the row coordinate u.  Per domain, the fit is
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
 * adds no bias beyond what the smoothers cannot represent, which SURE counts.  Against the former
 * fit (the same cosines times Chebyshev polynomials of one degree for all), the sky's RMS error
 * relative to the whole radiance at the nodes (8 urban sunset tables, 4 of the others, against
 * the mean of two tables at 16 times the paths, its noise taken out): urban sunset 1.15 -> 0.89%,
 * rural sun 30 0.29 -> 0.24%, desert dust sun 30 0.75 -> 0.64%, rural sun -4 0.93 -> 0.63%.  Rows
 * whose fitted luminance falls below 0.15 of their own mean somewhere (deep twilight's horizon, sun
 * below about -12) keep their raw nodes: the row weights would leave those dim nodes a large
 * relative error.
 *
 * In deep twilight a shape per node may be given (twilight_node_paths: the light of orders 1 and 2
 * along the node's view ray, scattered isotropically toward the observer).  The sky's nodes are then
 * fitted divided by it, and the fit multiplied back: within a row the ratio spans at most 3.4 times
 * where the nodes span 23 (rural, sun -18; -10: 4.8 and 13), so every row passes the range check
 * and the fit averages many more nodes (sun -18, twelve seeds, the rows fitted: nodes
 * of 11-21% relative noise come out at 4-13%, against 6-24% fitted as they are).  The rows within
 * 1.5 degrees of the horizon (final quality: 0, 0.25 and 1 degree, preview 0 and 0.74) are fitted
 * through the shape as a band of their own, across the azimuth only (a row's cosines kept as they
 * are, only the highest dropped): the ratio doubles there (the shape leaves out the higher orders,
 * which weigh most in the dense air that those rays alone cross), and fitting through that knee
 * biased the rows above.  Sun -18, 24 seeds, the fit's mean against the raw nodes' mean in blocks
 * of rows x columns, worst block: rows 1-4 degrees up, 36-60 degrees from the sun, +7.9% (z 6.5)
 * when the rows within 0.8 degrees took the plain fit of the whole sky and the rest the shaped
 * fit, +1.8% with the band; the band's rows 0.5-4.5% either way (z up to 3.3), against the
 * noise of 38% (69% before) at the horizon away from the sun and 10-22% elsewhere in the band.
 * Over twelve seeds the fit's mean stays within 1.3% of the raw nodes' mean in every block of
 * rows x thirds of the azimuth, sun -8 to -18 (at the twilight arch's peak, 5-12 degrees up toward
 * the sun, 0.7-1.2% low); the preview's coarser rows leave more (sun -14: the row 3 degrees up
 * toward the sun 4.8% high, the next two 3% low), against a noise that the shape takes from 8.1 to
 * 6.5%. */
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
 * together: rural sun -18, one node's X / Y is 4-7% noisy (10% at the horizon) where its Y is
 * 16-40%.  Yet the colour of a twilight map, whose R = 3.24 X - 1.54 Y - 0.50 Z is a small
 * difference of large terms, was noisier than its luminance (one map's R / G 13.3% at sun -18,
 * against 5%; with the ratios' fit 7.6%; B / G 5.7 -> 3.5%).  The ratios' variances come from
 * the jackknife over batches of a node's paths: to first order (the delta method) they came out 1.3
 * to 2.2 times too small at sun -18, which let the fit keep every cosine.  A node's ratio of means
 * is biased by its covariance with Y, at -18 below 0.3% of the ratio above the horizon's rows.
 * Nodes with a ratio that is not finite leave their domain raw. */
fm_status sky_grid_fit_chroma(sky_grid *g, double sun_elevation, const double *const ratio[2],
                              const double *const ratio_var[2]);

#endif

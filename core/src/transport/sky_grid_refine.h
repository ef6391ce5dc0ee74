/* A finer copy of a linear sky grid (sky_grid.h) by cubic interpolation between its nodes.
 *
 * A table's bilinear interpolant lies above a radiance that bends upward between its nodes (convex
 * in the row coordinate or the azimuth), and a coarse table's by more: deep twilight's clear sky,
 * which climbs steeply toward the horizon and toward the sun, came out about 1 % bright from the
 * preview's 12 x 12 sky nodes against the final's 20 x 16 (the live sky's maps read the preview's:
 * docs/decisions/2026-12-08-live-deep-bright.md).  Lookups on the refined grid follow a cubic through
 * the nodes (Catmull-Rom in u, then in the azimuth), whose error falls with the fourth power of the
 * node spacing instead of the second. */
#ifndef FM_TRANSPORT_SKY_GRID_REFINE_H
#define FM_TRANSPORT_SKY_GRID_REFINE_H

#include "transport/sky_grid.h"

/* fine (initialised here; free with sky_grid_free) with `factor` times the intervals of `coarse` in
 * each direction of each domain, its nodes on the coarse ones where they meet (the same values there);
 * between them the cubic through the four nearest nodes per direction, kept within their range (no
 * overshoot, never negative for non-negative values).  The azimuth is mirrored at 0 and pi (the sky's
 * symmetry about the sun's vertical), the zenith and nadir rows continue into the opposite azimuth,
 * the horizon rows extrapolate linearly.  coarse must be linear (not logarithmic).  FM_OK or
 * FM_ERR_OUT_OF_MEMORY. */
fm_status sky_grid_refine(const sky_grid *coarse, int factor, sky_grid *fine);

#endif

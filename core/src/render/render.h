/* Scheduling of a render: which estimator runs where, on how many threads, with which seeds.
 *
 * Fast path (preview, final): the radiance table of transport/sky_grid.h is filled twice, once with
 * single scattering by deterministic quadrature (fine grid) and once with all higher orders by path
 * tracing (coarse grid: that part of the sky is smooth; its noise then averaged by a fit,
 * sky_grid_fit.h), and every pixel averages table lookups over
 * its footprint.  The ground's reflection of skylight goes with the deterministic part, through the
 * diffuse ground irradiance (transport/ground_irradiance.h).  Reference: every pixel path-traces all orders itself, no table of radiance.
 * Both then add the sun disk, integrated over each pixel's footprint. */
#ifndef FM_RENDER_RENDER_H
#define FM_RENDER_RENDER_H

#include "firmament/firmament.h"

typedef struct quality_settings {
    int ss_rows_sky, ss_rows_ground, ss_cols; /* single-scattering table */
    int ms_rows_sky, ms_rows_ground, ms_cols; /* multiple-scattering table */
    int ms_paths;                             /* paths per multiple-scattering node */
    int ground_paths;                         /* paths per diffuse ground irradiance angle */
    int subpixels;                            /* footprint samples per pixel and axis */
    int reference_paths;                      /* reference: paths per pixel */
    int ss_points;                            /* single-scattering quadrature points per piece */
    int ground_rows, ground_cols;             /* the ground irradiance's order-1 quadrature */
    int guide_offsets;                        /* deep twilight: the sky guide's offsets toward the sun */
} quality_settings;

/* The settings of a quality level, with every sample count scaled by `scale`. */
quality_settings render_quality_settings(fm_quality quality, double scale);

#endif

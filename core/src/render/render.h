/* Scheduling of a render (fm_render): which estimator runs where, on how many threads, with which
 * seeds.
 *
 * Fast path (preview, final): the radiance table of transport/sky_grid.h is filled twice, once with
 * single scattering by deterministic quadrature (fine grid) and once with all higher orders by path
 * tracing (coarse grid: that part of the sky is smooth; its noise then averaged by a fit,
 * ms_table.h), and every pixel averages table lookups over its footprint.  The ground's reflection
 * of skylight goes with the deterministic part, through the diffuse ground irradiance
 * (transport/ground_irradiance.h).  Reference: every pixel path-traces all orders itself, no table
 * of radiance (reference.h).  Both then add the sun disk, integrated over each pixel's footprint
 * (sun_disk_raster.h); the image carries the render's record (record.h). */
#ifndef FM_RENDER_RENDER_H
#define FM_RENDER_RENDER_H

#include "firmament/firmament.h"
#include "render/quality.h"

#endif

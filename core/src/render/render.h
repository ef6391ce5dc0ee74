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
#include "render/render_job.h"

/* fm_render in steps, for the live sky (live.c) to make its tables and its maps alike.  The job
 * holds the sky (its sun), the parameters and a zeroed ms_table. */

/* Checks the parameters, sets the camera, the quality settings and the seed, and creates the image
 * (the render record filled). */
fm_status render_start(render_job *job, fm_error *err);
/* The twilight sampling with the sun below the observer's horizon plane (*tw NULL otherwise). */
fm_status render_twilight(render_job *job, twilight_sampling **tw, fm_error *err);
/* The fast path's tables into job->ss and job->ms (the caller frees them, and job->ground): needs
 * the job's sky, parameters, quality settings, seed, channels and twilight sampling, not its image. */
fm_status render_fast_tables(render_job *job, double sun_elevation, fm_error *err);
/* render_fast_tables in its three steps, the multiple-scattering table first (on the ground it
 * completes the ground's irradiance, which the single-scattering table's downward rows reflect):
 * begin (the deck, the tables' memory, the ground's irradiance), fill (the multiple-scattering
 * table, or fog's), end (the single-scattering table and the fit).  Jobs whose tables are
 * shareable (by day, no fog, ms_table_walk_shareable) may instead be filled together, their skies
 * differing only in the sun's elevation: their walks shared (ms_table_fill_shared). */
fm_status render_fast_tables_begin(render_job *job, fm_error *err);
fm_status render_fast_tables_fill(render_job *job, double sun_elevation, fm_error *err);
int render_fast_tables_shareable(const render_job *job);
fm_status render_fast_tables_fill_shared(render_job *const *jobs, int count, fm_error *err);
fm_status render_fast_tables_end(render_job *job, double sun_elevation, fm_error *err);
/* Frees what render_fast_tables made: job->ss, *job->ms (when set), job->ground and job->deck. */
void render_tables_free(render_job *job);
/* The fast path's pixels: footprint averages of job->ss and the multiple-scattering table ms. */
fm_status render_fast_pixels(render_job *job, const sky_grid *ms, fm_error *err);
/* The sun disk after a render that went well (status s FM_OK): the image goes to *out; else it is
 * freed and s returned. */
fm_status render_finish(render_job *job, fm_status s, fm_image **out, fm_error *err);

#endif

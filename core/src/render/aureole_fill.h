/* Filling the live sky's grid around the sun (aureole.h) from a render job's sky. */
#ifndef FM_RENDER_AUREOLE_FILL_H
#define FM_RENDER_AUREOLE_FILL_H

#include "render/aureole.h"
#include "render/render_job.h"

/* Fills the grid for the job's sky, whose sun stands at sun_elevation (rad), as the job's
 * single-scattering table is filled (render.c): the same estimator, points and ground. */
fm_status aureole_fill(aureole *a, const render_job *job, double sun_elevation);

#endif

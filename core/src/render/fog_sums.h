/* The column (fog_column.h) solved at every grid wavelength into the job's multiple-scattering
 * table's sums: lit by the beam and the air above the layer (the day's), or the layer alone lit by
 * the sky above it (the column lit from above, fog_incident.h). */
#ifndef FM_RENDER_FOG_SUMS_H
#define FM_RENDER_FOG_SUMS_H

#include "render/fog_column.h"

/* The column's sums into the table (t->sum and t->peak) and what it adds to the ground's irradiance
 * (ground; on_ground: whether the observer is there), lit by the beam and the air above the fog, or
 * (from_above) the column of the fog alone lit by the sky above it (tables; response: its map of
 * that light, shared between suns, or NULL). */
fm_status fog_column_sums(struct render_job *job, int from_above, fog_tables_fn tables, column_response *response,
                          double *ground, int *on_ground);

#endif

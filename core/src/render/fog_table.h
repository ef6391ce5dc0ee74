/* Fog around the observer, or a cloud deck above, around or below the observer: the fast path's
 * multiple-scattering table from a deterministic solution of the plane-parallel column instead of
 * paths (docs/decisions/2026-12-06-fog-column.md, docs/decisions/2026-12-06-cloud-column.md).
 *
 * In fog of a few hundred metres' visibility the table's paths are heavy-tailed (the droplets'
 * forward peak through several scatterings) and a map keeps percents of noise.  The atmosphere is
 * horizontally uniform and a view in such fog sees a few hundred metres, where the sphere does not
 * matter, so the radiance at the observer is that of a plane-parallel column: the fog, the air and
 * any clouds above cut into homogeneous layers, solved by adding-doubling (transport/plane_column.h)
 * with the droplets' peak truncated (delta-M), per grid wavelength, with the beam dimmed above the
 * fog as in the spherical atmosphere.  Under a deck the paths random-walk through it just as in fog;
 * the column holds the deck (its top where the fog's was) and the air below it in layers too.
 * Orders >= 2 are that solution less its single scattering; single scattering stays the exact
 * quadrature of the single-scattering table.
 *
 * Which sky takes it and how it is lit: fog_regime.h.  The column's layers: fog_column.h; their
 * solution into the table's sums: fog_sums.h; the droplets' truncated peak: fog_peak.h. */
#ifndef FM_RENDER_FOG_TABLE_H
#define FM_RENDER_FOG_TABLE_H

#include "firmament/firmament.h"
#include "render/fog_incident.h"
#include "render/fog_peak.h"
#include "render/fog_regime.h"

struct render_job;

/* The multiple-scattering table's size where the column fills it: its values are exact at the
 * nodes, and the forward light about the sun, a few degrees wide, wants nodes 2.5 degrees apart
 * there (the quality's are 5 by 12). */
#define FOG_TABLE_ROWS_SKY 40
#define FOG_TABLE_COLS 64
struct quality_settings;
void fog_table_size(struct quality_settings *q);

/* Fills the job's multiple-scattering table from the column (values and the sums the ground's
 * irradiance reads, one "path" per node), in place of its paths and fit; below the sun of
 * fog_table_from_above, tables makes the tables of the sky above the fog (fog_incident.h). */
fm_status fog_table_fill(struct render_job *job, fog_tables_fn tables);

#endif

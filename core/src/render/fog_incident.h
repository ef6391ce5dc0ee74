/* Fog (or a low deck) at a low sun and in twilight: the light that comes down on the layer's top from
 * the spherical sky above it, the fog column's incident field (render/fog_table.h,
 * docs/decisions/2026-12-07-twilight-fog.md).
 *
 * With the sun near or below the horizon the fog lies in the Earth's shadow or nearly: its light is
 * the twilit sky above it, which a plane column cannot make (its beam has no cosine) and the
 * sky's own estimators, with the observer above the fog, compute as for a clear sky.  So the sky is
 * built again without the fog, the observer at the fog's top and the ground as bright as the fog
 * and the ground under it seen from above (its diffuse albedo, so that the air sends back down what
 * it scatters of the fog's light), and its fast tables (single scattering, and multiple scattering
 * from paths) read at the column's Gauss nodes over the azimuth. */
#ifndef FM_RENDER_FOG_INCIDENT_H
#define FM_RENDER_FOG_INCIDENT_H

#include "firmament/firmament.h"
#include "transport/sky_grid.h"

struct render_job;
struct twilight_sampling;

typedef struct fog_incident {
    int K, streams, modes;
    double *field;  /* [K][streams][modes]: Fourier modes (L = I_0 + 2 sum_m I_m cos(m phi), phi from the
                     * sun's azimuth) of the downward radiance at the fog's top at the Gauss nodes */
    double *seen;   /* [node][K]: that radiance toward each sky node of the multiple-scattering table */
    double *single; /* [node][K]: its single scattering alone */
} fog_incident;

/* Makes the fast tables of a job (its sky, parameters, quality, seed and channels set): its twilight
 * sampling in *tw (the caller frees it), then render_fast_tables (render.h, whose module includes this
 * one's caller: it is passed down). */
typedef fm_status (*fog_tables_fn)(struct render_job *job, struct twilight_sampling **tw);

/* Builds it for the job's sky without its cloud layer `cloud` (the fog, top at fog_top_m), the ground
 * of albedo[k] per grid wavelength, at the Gauss nodes of a column of `streams` with `modes` Fourier
 * modes, and at the sky nodes of `nodes`.  The caller frees it with fog_incident_free (also after a
 * failure). */
fm_status fog_incident_build(const struct render_job *job, fog_tables_fn tables, int cloud, double fog_top_m,
                             const double *albedo, int streams, int modes, const sky_grid *nodes, fog_incident *out);
void fog_incident_free(fog_incident *f);

#endif

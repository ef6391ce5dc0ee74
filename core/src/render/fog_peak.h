/* The light the droplets' truncated peak scatters several times within a few degrees of the sun,
 * which the column (fog_column.h, delta-M) counts as unscattered: its table (ms_table.peak), added
 * to the single-scattering table about the sun. */
#ifndef FM_RENDER_FOG_PEAK_H
#define FM_RENDER_FOG_PEAK_H

#include "base/vec.h"
#include "firmament/firmament.h"
#include "render/fog_peak_view.h"

struct render_job;
struct fog_column;
struct scaled_layer;
struct plane_layer;

#define FOG_PEAK_ANGLES 512 /* the table ms_table.peak: uniform in sin(theta / 2) */
/* ms_table.peak's size: two tables of FOG_PEAK_ANGLES per wavelength, then the weights by view
 * (fog_peak_view.h) per wavelength */
#define FOG_PEAK_SIZE(K) ((size_t)(K) * (2 * FOG_PEAK_ANGLES + FOG_PEAK_VIEW_SIZE))

/* The peak's light at wavelength k (beam: the unscattered beam's radiance scale at the observer) in
 * ms_table.peak, and its flux on the ground in fc->ground[k]. */
fm_status fog_peak_light(struct fog_column *fc, const struct scaled_layer *sl, const struct plane_layer *pl, int k,
                         double beam);
/* The peak's light along view cosine mu over that along the sun's slant at wavelength k of K
 * (fog_peak_view.h): the tables hold it as along the beam. */
double fog_peak_view_at(const double *peak, int K, int k, double mu);
/* One of the peak's two tables at wavelength k, at cosine x from the sun. */
double fog_peak_at(const double *table, int k, double x);

/* Adds the light scattered several times within the droplets' truncated peak, within a few degrees
 * of the sun, to the single-scattering table (once it is filled; the table from the column holds its
 * negative part beyond, and its flux on the ground is already in). */
void fog_table_add_peak(struct render_job *job);
/* That light in view direction view, in the job's channels (0 without a peak): the live sky's
 * aureole (aureole.h), read around the sun in place of the single-scattering table, adds it too. */
void fog_table_peak(const struct render_job *job, vec3 view, float *add);

#endif

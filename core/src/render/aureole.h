/* The single-scattering radiance around the sun on a grid centred on it, for the live sky.
 *
 * The single-scattering table (sky_grid.h) is laid out by view elevation and azimuth relative to the
 * sun: around a high sun its rows are 2.9 degrees apart at preview quality, coarse for the aerosols'
 * forward peak, and between two sun elevations of the live sky's grid the peak moves with the sun
 * while the table is read at fixed relative directions.  This grid is laid out by the angle from the
 * sun gamma (rows crowded at the sun: gamma = AUREOLE_RADIUS u^2) and the angle around it psi (from
 * the direction toward the zenith, 0 to pi: the sky is symmetric about the sun's vertical plane), so
 * its resolution is the same at any sun, and interpolated between sun elevations it keeps the peak
 * on the sun.  Its values are the same estimator's as the table's (single_scatter_ray_radiance), in
 * logarithms; maps read it within AUREOLE_RADIUS of the sun, blended into the table toward its edge
 * and toward the horizon (aureole_weight). */
#ifndef FM_RENDER_AUREOLE_H
#define FM_RENDER_AUREOLE_H

#include "base/units.h"
#include "base/vec.h"
#include "firmament/firmament.h"

#define AUREOLE_RADIUS (10.0 * FM_DEG)
#define AUREOLE_ROWS 20
#define AUREOLE_COLS 13

typedef struct aureole {
    int channels;
    float *values; /* [AUREOLE_ROWS][AUREOLE_COLS][channels]: log(max(L, FM_GRID_FLOOR)) */
} aureole;

static inline size_t aureole_floats(const aureole *a) { return (size_t)AUREOLE_ROWS * AUREOLE_COLS * a->channels; }

fm_status aureole_init(aureole *a, int channels); /* zero values; FM_ERR_OUT_OF_MEMORY */
void aureole_free(aureole *a);

/* Where a direction lies around the sun: gamma and psi (rad). */
typedef struct aureole_place {
    double gamma, psi;
} aureole_place;

/* The frame of a sun at elevation sun_elevation (rad): directions given by their elevation e and
 * azimuth relative to the sun phi (rad). */
typedef struct aureole_frame {
    double sun, sin_s, cos_s, cos_radius;
} aureole_frame;

static inline aureole_frame aureole_frame_of(double sun_elevation)
{
    return (aureole_frame){sun_elevation, sin(sun_elevation), cos(sun_elevation), cos(AUREOLE_RADIUS)};
}

/* Whether (e, phi) lies within the grid, and where (*p). */
int aureole_locate(const aureole_frame *f, double e, double phi, aureole_place *p);

/* The direction (elevation e, azimuth relative to the sun phi, rad) at (gamma, psi). */
void aureole_direction(const aureole_frame *f, double gamma, double psi, double *e, double *phi);

/* gamma and psi of grid node (row, col). */
void aureole_node(int row, int col, double *gamma, double *psi);

/* The share (0 to 1) of the grid's value in a direction at p, elevation e, with the horizon at
 * horizon (rad): 1 within 0.6 of the radius, falling smoothly to 0 at its edge, and to 0 from 1.5
 * degrees above the horizon down to it (the grid's bilinear cells there would mix in the ground). */
double aureole_weight(const aureole_place *p, double e, double horizon);

/* The grid's log radiance at p, channel by channel (bilinear in sqrt(gamma) and psi). */
void aureole_lookup_log(const aureole *a, const aureole_place *p, float *out);

/* Whether a map with the sun at sun_elevation (rad), the horizon at `horizon` (rad), reads the grid:
 * its directions within AUREOLE_RADIUS of a sun lower than that are all below the horizon, where
 * aureole_weight is 0. */
static inline int aureole_seen(double sun_elevation, double horizon)
{
    return sun_elevation > horizon - AUREOLE_RADIUS;
}

/* v (channels of linear radiance: the single-scattering table's at elevation e and azimuth relative
 * to the sun phi, horizon at `horizon`, rad) blended with the grid's by aureole_weight, in logarithms. */
void aureole_blend(const aureole *a, const aureole_frame *f, double e, double phi, double horizon, float *v);

#endif

/* A direction guide for scattering vertices when the sun is below the horizon.
 *
 * At twilight nearly all the light that a vertex scatters comes from a narrow band of its sky: the
 * sunlit air toward the sun's azimuth, seen grazing over the Earth's shadow, a little below the
 * vertex's own horizon when it is high up.  The phase function does not know where that band is,
 * and the sun guide (path.h) aims at the sun, which is below the horizon.  This guide is a
 * piecewise-constant density over directions proportional to the single-scattering luminance
 * (deterministic quadrature, single_scatter.h) seen from a few altitudes above the observer, on a
 * grid of elevation (crowded at that altitude's horizon) x azimuth from the sun.  The atmosphere is
 * horizontally homogeneous, so a vertex near the observer sees nearly the sky of the level nearest
 * its altitude, laid out in its own frame (local horizontal, the sun's azimuth there) with the
 * level's horizon on the vertex's own (below: the sunlit band grazes the horizon); in deep
 * twilight there are levels farther toward the sun as well, and each cell's luminance adds the light
 * of order 2 seen that way (shadow_flight.h): in the shadow a point receives far more of it than of
 * single scattering.  The density is the same for every wavelength; it enters the path's spectral
 * MIS as a third technique beside the phase function and the sun guide (one-sample MIS, balance
 * heuristic).  Any density keeps the estimator unbiased; this one puts the directions where the
 * next order's sunlight is.
 *
 * The horizons lined up: a vertex between two levels' altitudes has its horizon lower or higher
 * than the nearest level's by the difference of their dips (a vertex 3 km above the level at 32 km:
 * 0.26 degrees, several of the guide's rows there), and the sunlit band seen from high up lies just
 * above the horizon, as thin as that.  So elevations are stretched linearly from the vertex's
 * horizon to the level's, between the horizon and the zenith and between the nadir and the horizon
 * (docs/decisions/2026-12-06-sky-guide.md). */
#ifndef FM_TRANSPORT_SKY_GUIDE_H
#define FM_TRANSPORT_SKY_GUIDE_H

#include "base/vec.h"
#include "firmament/firmament.h"


#define SKY_GUIDE_ALTITUDES 7
#define SKY_GUIDE_MAX_OFFSETS 6
/* and at most this many more per offset at a thin cloud layer's top in deep twilight
 * (sky_guide_build.h) */
#define SKY_GUIDE_EXTRA_LEVELS 4
#define SKY_GUIDE_LEVELS ((SKY_GUIDE_ALTITUDES + SKY_GUIDE_EXTRA_LEVELS) * SKY_GUIDE_MAX_OFFSETS)
#define SKY_GUIDE_ROWS_UP 40   /* elevation bins from the level's horizon to the zenith */
#define SKY_GUIDE_ROWS_DOWN 20 /* and from the nadir to the horizon */
#define SKY_GUIDE_ROWS (SKY_GUIDE_ROWS_UP + SKY_GUIDE_ROWS_DOWN)
#define SKY_GUIDE_COLS 36      /* azimuth bins over [0, 360) deg from the sun's azimuth */

typedef struct sky_guide_level {
    double radius;                                      /* m from the Earth's centre */
    double horizon;                                     /* rad: elevation of its horizon (<= 0) */
    int offset;                                         /* index of its distance toward the sun */
    int usable;                                         /* 0: this level's sky is black */
    int single_only;                                    /* 1: single scattering alone (sky_guide_extra) */
    double edge_sin[SKY_GUIDE_ROWS + 1];                /* sin(elevation) of the row edges, ascending */
    double cdf_row[SKY_GUIDE_ROWS + 1];                 /* marginal over rows */
    double cdf_col[SKY_GUIDE_ROWS][SKY_GUIDE_COLS + 1]; /* per row, over columns */
    double pdf[SKY_GUIDE_ROWS][SKY_GUIDE_COLS];         /* per steradian */
} sky_guide_level;

typedef struct sky_guide {
    int levels, offsets;
    double sun0;          /* rad: the sun's elevation at the observer */
    double bottom_radius; /* m: the ground's, for a vertex's horizon */
    int align_horizons;   /* 1 as built; 0 lays a level's sky over a vertex's by elevation alone */
    sky_guide_level level[SKY_GUIDE_LEVELS];
} sky_guide;

/* The distances toward the sun of the levels' offsets (degrees of arc). */
extern const double sky_guide_offset_deg[SKY_GUIDE_MAX_OFFSETS];

/* A direction at the vertex x (Earth-centred) from three uniform numbers, and the density of a
 * direction d there (per steradian). */
vec3 sky_guide_sample(const sky_guide *g, vec3 x, vec3 sun_dir, double u1, double u2, double u3);
double sky_guide_pdf(const sky_guide *g, vec3 x, vec3 sun_dir, vec3 d);

#endif

/* Adding-doubling for a plane-parallel column of homogeneous layers over a Lambertian ground, lit
 * by a parallel solar beam at its top: the diffuse downward radiance at the bottom, per azimuthal
 * Fourier mode, at given view cosines (Hansen & Travis 1974, Space Sci. Rev. 16, 527, section 2.6;
 * the adding of unlike layers: Plass, Kattawar & Catchings 1973, Appl. Opt. 12, 314).
 *
 * Each layer is solved by doubling from single scattering in a sliver of optical depth below
 * PLANE_COLUMN_TAU_START; the layers are added from the top down, and the ground couples through the
 * azimuthal mean only.  The view cosines (and the sun's) enter as points of zero quadrature weight,
 * so they do not change the integrals; only the columns of incidence that the beam's light reaches
 * (the Gauss nodes and the sun) are kept, which keeps the work at n x (N + 1) per matrix row.
 *
 * The caller scales the layers (delta-M: chi are the scaled phase function's moments, tau and ssa
 * the scaled ones) and corrects single scattering (render/fog_table.c).  Units: F0 = 1 on a surface
 * normal to the beam; radiances per unit F0, fluxes per unit mu0 F0. */
#ifndef FM_TRANSPORT_PLANE_COLUMN_H
#define FM_TRANSPORT_PLANE_COLUMN_H

#include "firmament/firmament.h"

#define PLANE_COLUMN_MAX_LAYERS 24

typedef struct plane_layer {
    double tau;        /* vertical optical depth */
    double ssa;        /* single-scattering albedo, [0, 1] */
    const double *chi; /* Legendre moments chi_0 .. chi_{2N-1} of the phase function (chi_0 = 1) */
    double mu0;        /* the beam's cosine within this layer, (0, 1], or 0 for the column's: pseudo-spherical
                        * (its slant optical depth across the layer, tau / mu0, the sphere's); the
                        * beam's direction and the radiances' normalisation stay the column's mu0 */
} plane_layer;

typedef struct plane_column {
    int streams;         /* N Gauss nodes per hemisphere, [2, 32]: 2N moments and 2N Fourier modes */
    int layer_count;     /* [1, PLANE_COLUMN_MAX_LAYERS] */
    const plane_layer *layer; /* the top layer first */
    double ground_albedo;
    double mu0;          /* the sun's zenith cosine, (0, 1] */
    int n_mu;            /* view cosines at the bottom, looking up, each in (0, 1] */
    const double *mu;
} plane_column;

/* Fourier modes of the diffuse downward radiance at the bottom: modes[k * 2N + m] for view cosine
 * mu[k], so that L(mu_k, phi) = modes[k 2N] + 2 sum_m modes[k 2N + m] cos(m phi), phi the azimuth
 * from the sun's side; *flux_down is the downward flux at the bottom (direct and diffuse, per mu0 F0,
 * the ground's light included).  FM_ERR_INVALID_ARGUMENT on a bad column, FM_ERR_OUT_OF_MEMORY. */
fm_status plane_column_bottom(const plane_column *c, double *modes, double *flux_down);

/* The same at the boundary above layer `level` (0: the top; layer_count: the bottom, as
 * plane_column_bottom): the downward radiance's modes in down (looking up) and the upward's in up
 * (looking down, mu the cosine below the horizontal; the ground's light included), either NULL when
 * not wanted (both NULL: the flux alone, from the azimuthal mean only), and the downward flux at that
 * level in *flux_down (may be NULL). */
fm_status plane_column_level(const plane_column *c, int level, double *down, double *up, double *flux_down);

/* The same lit from above by a diffuse field instead of the beam (c->mu0 and the layers' mu0 then
 * play no part): incident[j * 2N + m] the Fourier modes of the downward radiance at the column's top
 * at Gauss node j (plane_column_nodes), in the outputs' convention (L = I_0 + 2 sum_m I_m cos(m phi),
 * phi from the same azimuth).  down and up as plane_column_level's, in the field's units, hold only
 * light scattered at least once or reflected by the ground: the field seen through the layers along
 * a view, exp(-tau / mu) I(mu, phi), is the caller's to add.  *flux_down is the whole downward flux
 * at the level (the field's own transmitted part included), in the field's units times sr. */
fm_status plane_column_diffuse_level(const plane_column *c, int level, const double *incident, double *down,
                                     double *up, double *flux_down);
/* plane_column_diffuse_level's down as a linear map of the field, for fields that share a column:
 * response[(m * n_mu + k) * N + j] is mode m of the light at view k from a unit field in mode m at
 * Gauss node j (the modes do not mix), so down[k * 2N + m] = sum_j response[(m n_mu + k) N + j]
 * incident[j * 2N + m].  response holds 2N * n_mu * N values.  Errors as plane_column_level's. */
fm_status plane_column_diffuse_response(const plane_column *c, int level, double *response);
/* The column's Gauss nodes (zenith cosines, ascending), streams of them. */
void plane_column_nodes(int streams, double *mu);

#endif

/* The column of fog_table.h: its layers (the cloud layer, the air and any clouds above cut into
 * homogeneous layers, each species' column in each), their optical properties at a grid wavelength
 * delta-M scaled for the adding-doubling (transport/plane_column.h), the view and beam cosines.
 * Shared by the column's solution (fog_sums.h), the peak's light (fog_peak.h) and the table
 * (fog_table.c); not for other modules. */
#ifndef FM_RENDER_FOG_COLUMN_H
#define FM_RENDER_FOG_COLUMN_H

#include "atmosphere/atmosphere.h"
#include "firmament/firmament.h"
#include "render/fog_incident.h"
#include "spectrum/spectral_grid.h"
#include "transport/plane_column.h"

struct render_job;
struct sky_grid;

/* 12 streams (24 moments) with delta-M: the multiple scattering of orders >= 2 in the fog to well
 * under a percent of the 24-stream solution's (docs/decisions/2026-12-06-fog-column.md). */
#define FOG_STREAMS 12
#define FOG_MOMENTS (2 * FOG_STREAMS)

/* The column lit from above as a linear map of the field at its top (plane_column_diffuse_response)
 * at every grid wavelength: the same for each sun where the column's layers are (local_sun_sums). */
typedef struct column_response {
    double *values; /* [K][FOG_MOMENTS][rows_sky][FOG_STREAMS] */
    int ready;      /* filled by a column lit from above */
} column_response;

typedef struct fog_column {
    struct render_job *job;
    int layers;                    /* top first */
    int fog_layers;                /* the bottom fog_layers are the cloud and the air below it */
    int level;                     /* the observer's: the boundary below the first `level` layers */
    int on_ground;                 /* the observer on the ground (level == layers) */
    double column[PLANE_COLUMN_MAX_LAYERS][FM_MAX_SPECIES]; /* m^-2 */
    double *chi;                   /* [species][K][FOG_MOMENTS + 1] */
    int n_mu;
    double mu[512];                /* the sky rows' view cosines, then the ground rows' (looking down) */
    double top_radius;             /* the fog's top, m from the planet's centre */
    double top_m[PLANE_COLUMN_MAX_LAYERS]; /* each layer's top, m above the ground */
    double ground[FM_MAX_WAVELENGTHS]; /* what the column adds to the ground's irradiance */
    const fog_incident *incident;  /* at a low sun (fog_table_from_above): the light on the fog's top,
                                    * and the column the fog alone; else NULL */
    column_response *response;     /* with incident: its map of the field, or NULL (solved per field) */
} fog_column;

typedef struct scaled_layer {
    double tau, ssa, f;               /* unscaled optical depth and albedo; the truncated fraction */
    double chi[FOG_MOMENTS + 1];      /* the scaled moments */
} scaled_layer;

/* The layers' boundaries and every species' column in each (top layer first): the column's cloud
 * from base to fog_top (its top), the air below its base broken (none in fog), up to toa (m above
 * the ground: the atmosphere's top, or the fog's profile's for the fog alone). */
void fog_column_layers(fog_column *fc, const fm_sky *sky, double base, double fog_top, double toa);
/* fc->chi: every scattering species' Legendre moments at every grid wavelength. */
fm_status fog_species_moments(fog_column *fc, const atmosphere *atm);
/* Layer l's optical properties at wavelength k, delta-M scaled for the column (pl). */
void fog_layer_at(const fog_column *fc, const atmosphere *atm, int l, int k, scaled_layer *sl, plane_layer *pl);
/* The scaled phase function sum_l (2l + 1) chi_l P_l(x) / (4 pi) for l < FOG_MOMENTS. */
double fog_scaled_phase(const double *chi, double x);
/* The air layers' pseudo-spherical beam cosines (pl[l].mu0) above the fog at wavelength k. */
void fog_air_beam_cosines(const fog_column *fc, const fm_sky *sky, int k, const scaled_layer *sl, plane_layer *pl);
/* The fog's and the ground's diffuse albedo seen from above at every grid wavelength. */
fm_status fog_albedo(const fog_column *fc, double *albedo);
/* The view cosines of the table's rows (fc->mu); above every layer, the sky's as the sphere's. */
void fog_view_cosines(fog_column *fc, const struct sky_grid *g);
void fog_sphere_sky_cosines(fog_column *fc, const fm_sky *sky, const struct sky_grid *g);

#endif

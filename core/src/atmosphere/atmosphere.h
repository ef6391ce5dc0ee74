/* The atmosphere as the transport code sees it: a spherical shell between the ground and the top,
 * holding constituents ("species").  Each species is a number-density profile times per-wavelength
 * cross sections and a phase function, so a new constituent (aerosols, a custom gas) is a new
 * species, not a change to any estimator.
 *
 * Notation: r = distance from the planet's centre, mu = cosine of a direction's zenith angle at that
 * point, sigma_s / sigma_a / sigma_t = scattering / absorption / extinction (m^-1 for coefficients,
 * m^2 for cross sections), index k runs over the spectral grid. */
#ifndef FM_ATMOSPHERE_ATMOSPHERE_H
#define FM_ATMOSPHERE_ATMOSPHERE_H

#include "atmosphere/ozone_profile.h"
#include "atmosphere/profile.h"
#include "phase/phase.h"
#include "spectrum/spectral_grid.h"

#define FM_MAX_SPECIES 12
/* Cloud or fog, not haze (m^-1: an optical depth of 1 per km): where the sun table holds exact columns
 * and the paths take a thick medium's rules (roulette, guides, flights). */
#define FM_DENSE_SIGMA_PER_M 1e-3
#define FM_MAX_SHELLS 40

#define FM_MAX_EDGES (4 * FM_MAX_SPECIES) /* atmosphere.edge_altitude_m */

typedef struct species {
    const char *name;
    density_profile profile;
    double sigma_s[FM_MAX_WAVELENGTHS]; /* m^2 per particle */
    double sigma_a[FM_MAX_WAVELENGTHS];
    phase_function phase;
} species;

typedef struct atmosphere {
    double bottom_radius_m, top_radius_m;
    spectral_grid grid;                       /* solar irradiance already scaled to the date's distance */
    double ground_albedo[FM_MAX_WAVELENGTHS];
    int species_count;
    species species[FM_MAX_SPECIES];
    int scattering_count;                     /* species with a phase function come first */
    char species_names[FM_MAX_SPECIES][32];   /* storage for names read from a file */

    /* Delta-tracking majorants: shell i spans [shell_radius[i], shell_radius[i+1]]; for every grid
     * wavelength k, shell_majorant[i][k] >= sigma_t(r, lambda_k) for all r in the shell.  It is
     * sum_c species_sigma_t[c][k] shell_density_max[i][c], each species at its largest density in
     * the shell, so a majorant optical depth along a ray is a sum over species of the same form
     * (free_flight.h: one column per species per shell instead of one depth per wavelength). */
    int shell_count;
    double shell_radius[FM_MAX_SHELLS + 1];
    double shell_majorant[FM_MAX_SHELLS][FM_MAX_WAVELENGTHS];
    double shell_density_max[FM_MAX_SHELLS][FM_MAX_SPECIES]; /* m^-3, with headroom against rounding */
    double species_sigma_t[FM_MAX_SPECIES][FM_MAX_WAVELENGTHS]; /* m^2: sigma_s + sigma_a */

    /* Altitudes (m) where a species' profile bends sharply (the ends of the steps at an aerosol
     * layer's bottom and top), so quadratures along rays break at them (ray_pieces). */
    int edge_count;
    double edge_altitude_m[FM_MAX_EDGES];

    /* The grid spacing that every species' profile shares (m), or 0 when they differ; set by
     * atmosphere_update_majorants. */
    double profile_dz_m;
} atmosphere;

/* Builds molecules (U.S. Standard 1976 + Rayleigh after Bucholtz) and ozone (if column > 0) with
 * the given AFGL profile shape. */
fm_status atmosphere_init_clear_sky(atmosphere *atm, const spectral_grid *grid, double ozone_column_du,
                                    ozone_profile ozone_shape, double ground_albedo, fm_error *err);
void atmosphere_free(atmosphere *atm);

/* A zeroed slot for a new species, keeping scattering species before pure absorbers; NULL when
 * FM_MAX_SPECIES are in use. */
species *atmosphere_new_species(atmosphere *atm, int scatters);

/* Computes the majorant shells (for any top of the atmosphere) and the species' profile edges; call
 * after the species are final. */
void atmosphere_update_majorants(atmosphere *atm);

/* Number densities of every species at radius r. */
static inline void atmosphere_densities(const atmosphere *atm, double r, double *n)
{
    double z = r - atm->bottom_radius_m;
    if (atm->profile_dz_m > 0.0) {
        /* one grid for all: one division and one cell, the same values (a tenth of the sky
         * tables' build, and a fifth of the column quadratures') */
        const int S = atm->species_count;
        double f = z / atm->profile_dz_m;
        if (f <= 0.0) {
            for (int c = 0; c < S; c++)
                n[c] = atm->species[c].profile.n[0];
            return;
        }
        int i = (int)f;
        double t = f - i;
        for (int c = 0; c < S; c++)
            n[c] = profile_density_between(&atm->species[c].profile, f, i, t);
        return;
    }
    for (int c = 0; c < atm->species_count; c++)
        n[c] = profile_density(&atm->species[c].profile, z);
}

/* Scattering and extinction coefficients (m^-1) for every grid wavelength, from the species
 * densities n (atmosphere_densities) or at radius r. */
void atmosphere_coefficients_from_densities(const atmosphere *atm, const double *n, double *sigma_s, double *sigma_t);
void atmosphere_coefficients(const atmosphere *atm, double r, double *sigma_s, double *sigma_t);

/* Optical depth for grid wavelength k of a set of species columns (particles m^-2; species_sigma_t
 * is set by atmosphere_update_majorants). */
static inline double atmosphere_optical_depth(const atmosphere *atm, const double *columns, int k)
{
    double tau = 0.0;
    for (int c = 0; c < atm->species_count; c++)
        tau += atm->species_sigma_t[c][k] * columns[c];
    return tau;
}

/* The optical depths of every grid wavelength for a set of species columns, all at once:
 * depth[k] = sum_c species_sigma_t[c][k] columns[c] (set by atmosphere_update_majorants). */
void atmosphere_optical_depths(const atmosphere *atm, const double *columns, double *depth);

/* exp(-optical depth) of every grid wavelength for a set of species columns: T[k]. */
void atmosphere_transmittances(const atmosphere *atm, const double *columns, double *T);

#endif

/* Cloud layers as constituents of the atmosphere (docs/clouds.md): horizontally uniform slabs of
 * water droplets or ice crystals between a base and a top, each one scattering species.
 *
 * Water clouds: Mie theory (aerosol/mie.h) over OPAC's modified gamma droplet spectra
 * (aerosol/mie_lognormal.h; Hess, Koepke & Schult 1998), computed at every grid wavelength when the
 * layer is added, with liquid water's refractive index (data/water_index.c, Hale & Querry 1973 as
 * OPAC tabulates it).  The phase function is tabulated on CLOUD_ANGLE_COUNT angles quadratic in the
 * scattering angle, so the diffraction peak (width ~ lambda / (2 pi r_eff), 0.3 degrees for 7 um
 * droplets at 400 nm) spans tens of nodes; sampling inverts the table exactly (phase/phase_table.h).
 *
 * Ice clouds: extinction independent of wavelength (crystals much larger than the wavelength:
 * Q_ext = 2), no absorption in the visible, and a two-term Henyey-Greenstein phase function
 * (Kattawar 1975) p = f HG(g1) + (1 - f) HG(-g2) with the asymmetry parameter of cirrus, and 5 % of
 * the scattered light in a 22-degree halo (aerosol/ice_halo.h).
 *
 * A layer's amount is its optical depth at 550 nm, given directly, from a liquid water path
 *     tau = LWP * beta_ext / LWC = LWP * C_ext / (rho_w <V>)   (exact Mie; ~ 3 LWP / (2 rho_w r_eff)),
 * or, for fog, from the visibility V (Koschmieder): beta_ext(550 nm) = 3.912 / V. */
#ifndef FM_AEROSOL_CLOUD_H
#define FM_AEROSOL_CLOUD_H

#include "aerosol/mie_lognormal.h"
#include "atmosphere/atmosphere.h"

#define CLOUD_ANGLE_COUNT 601       /* theta_j = pi (j / 600)^2 */
#define CLOUD_KOSCHMIEDER 3.912     /* -ln(0.02) */
#define CLOUD_WATER_DENSITY 1000.0  /* kg m^-3 */

typedef struct cloud_type {
    const char *name;        /* "stratus", ... (the --cloud names) */
    int ice;                 /* 0: water droplets (Mie), 1: ice crystals (two-term HG) */
    modified_gamma_size size; /* water: the droplet spectrum */
    const char *source;      /* where the droplet spectrum comes from */
} cloud_type;

/* The built-in types, in the order --help lists them; NULL-named sentinel at the end. */
extern const cloud_type cloud_types[];

/* The type named name, or NULL. */
const cloud_type *cloud_type_find(const char *name);

/* "stratus, stratocumulus, ...": the names, comma-separated. */
void cloud_type_names(char *out, size_t size);

/* Per-particle optics of a water type at one wavelength (nm); phase (CLOUD_ANGLE_COUNT values at
 * cloud_angle_rad) may be NULL. */
fm_status cloud_water_optics(const cloud_type *t, double lambda_nm, mie_lognormal_result *out, double *phase,
                             fm_error *err);

/* theta_j of the phase tables (radians). */
double cloud_angle_rad(int j);

/* Ice phase function (sr^-1) and its asymmetry parameter. */
double cloud_ice_phase(double cos_theta);
double cloud_ice_asymmetry(void);

/* Optical depth at 550 nm of a liquid water path (g m^-2) of a water type. */
fm_status cloud_tau_from_lwp(const cloud_type *t, double lwp_gm2, double *tau550, fm_error *err);

#endif

/* Aerosols in the atmosphere: a biome's layers become scattering species whose cross sections,
 * single-scattering albedo and phase function come from the OPAC component tables
 * (aerosol/aerosol_optics.h, Mie theory), mixed externally in proportion to number density:
 *     sigma_s(lambda) = sum_i N_i sigma_s,i(lambda),
 *     p(lambda, theta) = sum_i N_i sigma_s,i p_i / sum_i N_i sigma_s,i.
 * Hygroscopic components are interpolated linearly in relative humidity between OPAC's tabulated
 * humidities (0, 50, 70, 80, 90, 95, 98, 99 %); all properties are interpolated linearly in
 * wavelength between the 20 nm table nodes. */
#ifndef FM_AEROSOL_AEROSOL_H
#define FM_AEROSOL_AEROSOL_H

#include "aerosol/aerosol_optics.h"
#include "aerosol/biome.h"
#include "atmosphere/atmosphere.h"

/* One component's properties per particle at a humidity and wavelength (300-1000 nm). */
typedef struct component_optics {
    double ext_m2, sca_m2, g;
    double phase[AEROSOL_ANGLE_COUNT]; /* sr^-1 at aerosol_optics_angle_rad(j) */
} component_optics;

/* Fails (invalid argument) for a component without a table. with_phase = 0 skips the phase. */
fm_status component_optics_at(const char *code, double humidity_percent, double lambda_nm, int with_phase,
                              component_optics *out, fm_error *err);

/* Vertical optical properties of a biome at one wavelength (300-1000 nm). */
typedef struct aerosol_column {
    double tau_ext, tau_sca; /* optical depths from the ground to the top */
    double g;                /* scattering-weighted asymmetry parameter */
    double ext_ground_per_m; /* extinction coefficient at the ground (layers starting there) */
} aerosol_column;

/* Adds the biome's layers to the atmosphere as scattering species (before the absorbers), with
 * number densities multiplied by turbidity and hygroscopic growth at humidity_percent (layers
 * with their own fixed humidity keep it).  Layers without scattering are left out, so turbidity 0
 * adds nothing.  Call atmosphere_update_majorants afterwards. */
fm_status aerosol_add_biome(atmosphere *atm, const biome *b, double humidity_percent, double turbidity,
                            fm_aerosol_phase model, fm_error *err);

/* The column of the biome (turbidity 1) at a wavelength, exactly as aerosol_add_biome's profiles
 * hold it. */
fm_status aerosol_biome_column(const biome *b, double humidity_percent, double lambda_nm, aerosol_column *out,
                               fm_error *err);

#endif

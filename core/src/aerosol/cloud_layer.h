/* A cloud layer as a constituent of the atmosphere (docs/clouds.md): a horizontally uniform slab of
 * one cloud type (aerosol/cloud.h) whose optics come from aerosol/cloud_optics.h. */
#ifndef FM_AEROSOL_CLOUD_LAYER_H
#define FM_AEROSOL_CLOUD_LAYER_H

#include "aerosol/cloud.h"

/* Adds one layer (type, base and thickness in m above the ground, optical depth at 550 nm) as a
 * scattering species whose vertical optical depth at 550 nm is exactly tau550 for the profile the
 * estimators see.  threads: for the per-wavelength Mie integrals (0 = all cores); cache_dir: where
 * water types' optics are kept between builds (aerosol/cloud_optics.h), NULL for none;
 * truncate_peak: the forward peak cut (delta-M, cloud_truncate_peak) and its share taken out of the
 * scattering coefficient, for the fast path's multiple scattering under a deck (sky.h).  Call
 * atmosphere_update_majorants afterwards. */
fm_status cloud_add_layer(atmosphere *atm, const cloud_type *t, double base_m, double thickness_m, double tau550,
                          int threads, const char *cache_dir, int truncate_peak, fm_error *err);

/* Cuts the forward peak (within 3 degrees) of one wavelength's phase values at the ascending angles
 * theta (n of them) to its value at the cut, and returns the fraction of the scattering it held
 * (delta-M), as phase_table.h normalises. */
double cloud_truncate_peak(double *values, const double *theta, int n);

/* Length (m) inside the spherical shell [r_base, r_top] of the straight line from radius r (m)
 * outward with direction cosine mu > 0 (toward the sun): times a layer's extinction, the optical
 * depth in front of the sun's disk. */
double cloud_shell_chord_m(double r, double mu, double r_base, double r_top);

#endif

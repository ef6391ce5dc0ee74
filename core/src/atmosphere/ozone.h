/* Ozone: absorption only.
 *
 * Cross section: Bogumil et al. (2003), IUP Bremen (data/ozone_bogumil2003.c), 1 nm bin means,
 * evaluated at one effective temperature: the ozone-weighted mean temperature of the profile
 * (about 225 K for the U.S. Standard profile).  In the visible the temperature dependence is a few
 * percent; it matters in the Huggins band below 340 nm.
 * Vertical profile: the shape of the U.S. Standard ozone profile (AFGL, atmosphere/ozone_profile.h),
 * maximum near 22 km, scaled to the requested total column.  The other AFGL profiles, chosen by
 * latitude and season, are in atmosphere/ozone_profile.h; the two profile functions below are
 * its U.S. Standard case. */
#ifndef FM_ATMOSPHERE_OZONE_H
#define FM_ATMOSPHERE_OZONE_H

/* m^2 per molecule at lambda (nm, 300-1000) and temperature (K). */
double ozone_cross_section_m2(double lambda_nm, double temperature_k);

/* Number density (m^-3) at altitude for a total column of 1 DU (U.S. Standard profile). */
double ozone_number_density_per_du(double altitude_m);

/* Ozone-weighted mean temperature (K) of the U.S. Standard profile (AFGL temperatures). */
double ozone_effective_temperature_k(void);

#endif

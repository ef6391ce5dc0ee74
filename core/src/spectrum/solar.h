/* Extraterrestrial solar spectral irradiance at 1 AU (ASTM G173-03 ETR, data/solar_astm_g173.c). */
#ifndef FM_SPECTRUM_SOLAR_H
#define FM_SPECTRUM_SOLAR_H

/* W m^-2 nm^-1 at lambda (nm), linear between table samples; 0 outside 299-1001 nm. */
double solar_irradiance_at(double lambda_nm);

/* Hat-weighted mean over [c - h, c + h]: integral(E(l) hat(l)) / h, W m^-2 nm^-1. */
double solar_irradiance_hat_mean(double c_nm, double h_nm);

#endif

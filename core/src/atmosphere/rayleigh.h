/* Molecular (Rayleigh) scattering by dry air.
 *
 * Cross section: the fit of A. Bucholtz, "Rayleigh-scattering calculations for the terrestrial
 * atmosphere", Appl. Opt. 34 (1995) 2765, which includes the King correction for depolarisation:
 *     sigma = A lambda^-(B + C lambda + D / lambda) cm^2, lambda in micrometres.
 * Depolarisation: the King factor of air from Bates (1984) as used by Bodhaine et al. (1999),
 *     F = (78.084 F_N2 + 20.946 F_O2 + 0.934 F_Ar + 0.036 F_CO2) / 100.0,
 * with depolarisation ratio rho = 6 (F - 1) / (3 + 7 F) and gamma = rho / (2 - rho) for the phase
 * function (phase/phase_rayleigh.h). */
#ifndef FM_ATMOSPHERE_RAYLEIGH_H
#define FM_ATMOSPHERE_RAYLEIGH_H

double rayleigh_cross_section_m2(double lambda_nm);
double rayleigh_king_factor(double lambda_nm);
double rayleigh_depolarization_ratio(double lambda_nm);
double rayleigh_gamma(double lambda_nm);

#endif

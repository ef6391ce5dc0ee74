/* U.S. Standard Atmosphere 1976 (NOAA/NASA/USAF, 1976), computed from its defining layers: linear
 * temperature segments in geopotential altitude and the hydrostatic law give pressure, and the
 * ideal gas law gives the number density.
 *
 * Below 86 km geometric altitude this is the standard itself (constant mean molecular weight).
 * Above, the standard switches to a diffusive, composition-dependent model that firmament does not
 * reproduce: the 86 km layer is continued isothermally.  The air column above 86 km is about 4e-6
 * of the total, so this changes no optical depth at the 1e-5 level. */
#ifndef FM_ATMOSPHERE_STANDARD_ATMOSPHERE_H
#define FM_ATMOSPHERE_STANDARD_ATMOSPHERE_H

double us76_temperature_k(double altitude_m);
double us76_pressure_pa(double altitude_m);
/* Molecules per cubic metre. */
double us76_number_density(double altitude_m);

#endif

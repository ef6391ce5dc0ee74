/* Units and physical constants.  SI inside the library (metres, seconds, kelvin, pascal);
 * wavelengths in nanometres because every data table uses them. */
#ifndef FM_BASE_UNITS_H
#define FM_BASE_UNITS_H

#define FM_PI 3.14159265358979323846
#define FM_DEG (FM_PI / 180.0) /* 30 * FM_DEG is 30 degrees in radians */

#define FM_KM 1000.0                       /* metres */
#define FM_CM2 1e-4                        /* square metres */
#define FM_DU_MOLECULES_PER_M2 2.6867e20   /* one Dobson unit: 2.6867e16 molecules cm^-2 */
#define FM_LUMINOUS_EFFICACY 683.0         /* lm/W at 555 nm: Y * 683 = cd/m^2 or lux */

/* Geometry of the planet (ARCHITECTURE.md section 2). */
#define FM_EARTH_RADIUS_M (6371.0 * FM_KM)
#define FM_ATMOSPHERE_HEIGHT_M (100.0 * FM_KM)

/* The Sun: IAU 2015 nominal solar radius over the astronomical unit gives the mean angular radius
 * 695700 km / 149597870.7 km = 4.6505e-3 rad = 0.26645 degrees. */
#define FM_SUN_RADIUS_M 6.957e8
#define FM_ASTRONOMICAL_UNIT_M 1.495978707e11

#endif

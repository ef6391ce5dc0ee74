/* Total ozone column by date and place: the closed-form climatology of van Heuklon (1979).
 *
 * T. K. van Heuklon, "Estimating atmospheric ozone for solar radiation models", Solar Energy 22
 * (1979) 63-68.  With phi the latitude, lambda the longitude (east positive) and E the day of year,
 * all angles in degrees,
 *
 *     O3 [DU] = J + (A + C sin(D (E + F)) + G sin(H (lambda + I))) sin^2(B phi)
 *
 *                         A     B     C    D       F        G   H   I          J
 *     northern (phi > 0)  150   1.28  40   0.9865  -30      20  3   20 or 0    235
 *     southern (phi < 0)  100   1.5   30   0.9865  152.625  20  2   -75        235
 *
 * The terms are the equatorial annual mean (J), the rise toward the poles (A), the seasonal cycle
 * (C; maximum on day 121, 1 May, in the north and day 304, 31 October, in the south: the spring
 * maxima) and a longitudinal wave (G; three waves round the northern hemisphere, two round the
 * southern).  Both hemispheres give J = 235 DU at the equator.
 *
 * The I coefficient in the north: 20 for eastern longitudes (lambda >= 0) and 0 for western ones
 * (lambda < 0).  This is how the public implementations of the fit read it (Broenkow and Flora's
 * MATLAB ozone_, 1997; R. Wilson's Python version, 2015), and it is the reading that reproduces
 * their published example 36 N, 122 W, day 185 -> 321.2 DU.  A single I = 20 everywhere gives
 * 330.7 DU there, and feeding the west-positive longitude +122 gives 331.8 DU (I = 20) or 323.4 DU
 * (I = 0).  The switch makes the northern field jump at the prime meridian (by 17.3 sin^2(B phi) DU)
 * and at 180 degrees (by the same amount): an artefact of the fit, kept so that the published
 * numbers come out.
 *
 * Accuracy: a fit to observations from before 1979 (before the Antarctic ozone hole and the
 * decline of the 1980s-90s), in a deliberately coarse form.  Expect errors of a few tens of DU
 * against modern satellite climatologies; at the equator, for instance, it gives 235 DU all year
 * where measured means are about 250-280 DU.  One public comparison reports misses of about 69 DU
 * (London, too high) and 173 DU (Nairobi, too low); we have not reproduced those.  It knows
 * nothing of the Antarctic ozone hole: over Antarctica in September-November it gives its largest
 * southern values (about 300-365 DU) where modern springs often bring well under 200 DU.  Good
 * enough to pick a plausible column for a rendered sky; not for UV-index work. */
#ifndef FM_ATMOSPHERE_OZONE_CLIMATOLOGY_H
#define FM_ATMOSPHERE_OZONE_CLIMATOLOGY_H

#include "firmament/firmament.h"

/* Total column (DU) at latitude [-90, 90] degrees (north positive), longitude in degrees east
 * (any value; wrapped into [-180, 180)), day of year 1-366. */
double ozone_climatology_column_du(double latitude_deg, double longitude_deg, int day_of_year);

/* The same for a Gregorian calendar date in 1900-2100.  Fails with FM_ERR_INVALID_ARGUMENT and one
 * line naming the field ("date", "latitude_deg", "longitude_deg") when an input is out of range. */
fm_status ozone_climatology_for_date(int year, int month, int day, double latitude_deg, double longitude_deg,
                                     double *column_du, fm_error *err);

#endif

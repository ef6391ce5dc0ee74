/* Delta T = TT - UT, the difference between Terrestrial Time (uniform, the time of the ephemerides)
 * and Universal Time (the Earth's rotation), in seconds.
 *
 * Estimate: the polynomials of F. Espenak and J. Meeus, "Five Millennium Canon of Solar Eclipses:
 * -1999 to +3000", NASA/TP-2006-214141 (2006), section 2.6, evaluated at the decimal year
 * y = year + (month - 0.5) / 12.  They reproduce the observed values to about a second over
 * 1900-2005 (compare the Astronomical Almanac's table: 63.8 s in 2000), predict 2005-2150 (69 s in
 * 2023 against 69.2 s measured), and outside -500..2150 fall back to the long-term parabola
 * -20 + 32 u^2 with u = (y - 1820) / 100 (Morrison & Stephenson 2004).  Before 1600 and in the
 * future the uncertainty grows to minutes and more: ΔT can be given explicitly instead. */
#ifndef FM_SUN_DELTA_T_H
#define FM_SUN_DELTA_T_H

/* Estimated Delta T in seconds for the middle of the month (any year; month 1-12). */
double delta_t_estimate_s(int year, int month);

#endif

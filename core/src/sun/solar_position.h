/* The sun's position in the sky: NREL's Solar Position Algorithm (SPA).
 *
 * I. Reda and A. Andreas, "Solar position algorithm for solar radiation applications", Solar Energy
 * 76 (2004) 577-589; NREL/TP-560-34302 (revised 2008).  Uncertainty +-0.0003 degrees in zenith and
 * azimuth for the years -2000 to 6000, given Delta T.
 *
 * The chain, each step a function of the one before (section numbers of the paper, section 3):
 *   3.1  Julian day JD of the UT instant (Meeus' formula; Julian calendar before 1582-10-15), the
 *        ephemeris day JDE = JD + Delta T / 86400, and centuries / millennia from J2000.0;
 *   3.2  the Earth's heliocentric longitude L, latitude B and radius R from the truncated VSOP87
 *        series (data/spa_terms.c, table A4.2): sum_i (sum_j A cos(B + C JME)) JME^i;
 *   3.3  the Sun's geocentric longitude Theta = L + 180 and latitude beta = -B;
 *   3.4  nutation in longitude (delta psi) and obliquity (delta epsilon) from the 63 IAU 1980 terms
 *        (table A4.3) over five fundamental arguments of the Moon and the Sun;
 *   3.5  the true obliquity epsilon = epsilon0 (Laskar's polynomial) + delta epsilon;
 *   3.6-3.7  aberration -20.4898" / R and the apparent longitude lambda;
 *   3.8  apparent sidereal time at Greenwich nu;
 *   3.9-3.10  geocentric right ascension alpha and declination delta;
 *   3.11 local hour angle H = nu + longitude - alpha;
 *   3.12-3.13 parallax (equatorial horizontal parallax 8.794" / R, the observer on the ellipsoid of
 *        flattening 1/298.257 at elevation E) giving topocentric alpha', delta', H';
 *   3.14 topocentric elevation, refraction, zenith angle; 3.15 azimuth from north toward east.
 * Appendix A.1: the equation of time; A.2: sunrise, transit and sunset by interpolating alpha and
 * delta between three days, here the days that start at local midnight of the date, so that the
 * three events are those of the local date.
 *
 * The code is written from the paper's equations; the tables are data (data/spa_terms.c). */
#ifndef FM_SUN_SOLAR_POSITION_H
#define FM_SUN_SOLAR_POSITION_H

#include "firmament/firmament.h"

/* Every intermediate quantity of one evaluation, named as in the paper (angles in degrees). */
typedef struct spa_state {
    double jd, jde;               /* Julian day (UT) and Julian ephemeris day (TT) */
    double jc, jce, jme;          /* centuries (UT, TT) and millennia (TT) from J2000.0 */
    double l_deg, b_deg, r_au;    /* Earth heliocentric longitude [0, 360), latitude, radius vector */
    double theta_deg, beta_deg;   /* geocentric longitude and latitude of the Sun */
    double x_deg[5];              /* fundamental arguments X0..X4 */
    double delta_psi_deg;         /* nutation in longitude */
    double delta_epsilon_deg;     /* nutation in obliquity */
    double epsilon0_arcsec;       /* mean obliquity */
    double epsilon_deg;           /* true obliquity */
    double aberration_deg;        /* delta tau */
    double lambda_deg;            /* apparent sun longitude */
    double nu0_deg, nu_deg;       /* mean and apparent sidereal time at Greenwich */
    double alpha_deg, delta_deg;  /* geocentric right ascension [0, 360) and declination */
    double h_deg;                 /* local hour angle [0, 360) */
    double xi_deg;                /* equatorial horizontal parallax */
    double delta_alpha_deg;       /* parallax in right ascension */
    double alpha_prime_deg, delta_prime_deg, h_prime_deg; /* topocentric */
    double e0_deg;                /* topocentric elevation without refraction */
    double delta_e_deg;           /* refraction correction (0 when off or below -0.8333 degrees) */
    double e_deg;                 /* apparent topocentric elevation */
    double zenith_deg;
    double azimuth_astro_deg;     /* Gamma: westward from south */
    double azimuth_deg;           /* Phi: eastward from north, [0, 360) */
    double eot_min;               /* equation of time */
} spa_state;

/* Julian day of a calendar date (Gregorian from 1582-10-15, Julian before) with the day's
 * fraction in `day` (e.g. 17.5 = noon of the 17th, UT). */
double spa_julian_day(int year, int month, double day);

/* 1 if (year, month, day) is a date of that calendar with year in [-2000, 6000]. */
int spa_date_is_valid(int year, int month, int day);

/* Sections 3.1-3.10: time scales, Earth position, nutation, obliquity, apparent sun, sidereal
 * time, geocentric right ascension and declination at the UT instant jd. */
void spa_geocentric(double jd, double delta_t_s, spa_state *s);

/* The whole chain for the (already validated) inputs, with delta_t_s resolved (not the estimate
 * sentinel): fills s. */
void spa_evaluate(const fm_solar_params *p, double delta_t_s, spa_state *s);

/* Appendix A.2: sunrise, transit and sunset (local clock hours) of the local date. */
void spa_rise_transit_set(const fm_solar_params *p, double delta_t_s, fm_solar_position *out);

/* Checks every input; field names as fm_solar_position_compute reports them. */
fm_status spa_validate(const fm_solar_params *p, fm_error *err);

#endif

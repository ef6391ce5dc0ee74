/* Vertical ozone profiles by latitude band and season: the six AFGL model atmospheres
 * (Anderson et al. 1986, data/afgl_profiles.c), each normalised to a 1 DU column, with their
 * temperatures for the ozone-weighted effective temperature of the cross section.
 *
 * Choice by place and date (the latitude bands of the AFGL models, which describe 15 N, 45 N and
 * 60 N):
 *   |latitude| < 23 degrees        tropical, all year
 *   23 <= |latitude| <= 60         midlatitude summer or winter
 *   |latitude| > 60                subarctic summer or winter
 * The AFGL summer and winter models describe July and January.  A day counts as northern summer
 * when it is nearer (in days, round the year) to 15 July (day 196) than to 15 January (day 15):
 * days 106-287, 16 April to 14 October in a common year (a day earlier in leap years; ignored).
 * The southern hemisphere has the opposite season on the same day. */
#ifndef FM_ATMOSPHERE_OZONE_PROFILE_H
#define FM_ATMOSPHERE_OZONE_PROFILE_H

/* Same order as the rows of fm_afgl_profiles (tools/make_tables.py). */
typedef enum ozone_profile {
    OZONE_PROFILE_US_STANDARD = 0, /* U.S. Standard 1976 (afglus): 344 DU as tabulated */
    OZONE_PROFILE_TROPICAL,        /* afglt:  282 DU */
    OZONE_PROFILE_MIDLATITUDE_SUMMER, /* afglms: 334 DU */
    OZONE_PROFILE_MIDLATITUDE_WINTER, /* afglmw: 378 DU */
    OZONE_PROFILE_SUBARCTIC_SUMMER,   /* afglss: 348 DU */
    OZONE_PROFILE_SUBARCTIC_WINTER,   /* afglsw: 376 DU */
    OZONE_PROFILE_COUNT
} ozone_profile;

#define OZONE_NORTHERN_SUMMER_FIRST_DAY 106 /* 16 April in a common year */
#define OZONE_NORTHERN_SUMMER_LAST_DAY 287  /* 14 October */

/* The profile for latitude (degrees, north positive) and day of year (1-366). */
ozone_profile ozone_profile_for(double latitude_deg, int day_of_year);

/* Short name ("us-standard", "tropical", "midlatitude-summer", ...); NULL for an invalid p. */
const char *ozone_profile_name(ozone_profile p);

/* Number density (m^-3) at altitude for a 1 DU column between the ground and the top of the
 * atmosphere (FM_ATMOSPHERE_HEIGHT_M): log-linear between the AFGL levels, held constant below 0
 * and above 120 km.  0 for an invalid p. */
double ozone_profile_density_per_du(ozone_profile p, double altitude_m);

/* Ozone-weighted mean temperature (K) over the column, integral n T dz / integral n dz, from the
 * profile's own temperatures; 0 for an invalid p. */
double ozone_profile_effective_temperature_k(ozone_profile p);

/* Column of the profile as tabulated, before normalisation (DU, ground to the top of the
 * atmosphere); 0 for an invalid p. */
double ozone_profile_tabulated_column_du(ozone_profile p);

#endif

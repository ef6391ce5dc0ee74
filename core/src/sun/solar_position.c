#include "sun/solar_position.h"

#include "base/param_range.h"
#include "base/status.h"
#include "base/units.h"
#include "data/spa_terms.h"
#include "sun/delta_t.h"

#include <math.h>

#define SPA_MIN_YEAR (-2000)
#define SPA_MAX_YEAR 6000
/* The sun's centre at sunrise and sunset: 34' of refraction and the 16' radius below the horizon. */
#define SPA_RISE_SET_ELEVATION_DEG (-0.8333)
/* SPA's refraction is applied while the true elevation is above -(sun radius + horizon refraction). */
#define SPA_REFRACTION_LIMIT_DEG (-(0.26667 + 0.5667))
/* Earth: equatorial radius (m) and polar over equatorial radius, 1 - 1/298.257 (paper, eq. 38-40). */
#define SPA_EARTH_RADIUS_M 6378140.0
#define SPA_EARTH_AXIS_RATIO 0.99664719

static double limit_degrees(double deg)
{
    double d = fmod(deg, 360.0);
    return d < 0.0 ? d + 360.0 : d;
}

/* Into [-180, 180). */
static double limit_degrees_signed(double deg)
{
    double d = limit_degrees(deg);
    return d >= 180.0 ? d - 360.0 : d;
}

static double limit_unit(double x)
{
    return x - floor(x);
}

static double sind(double deg)
{
    return sin(deg * FM_DEG);
}

static double cosd(double deg)
{
    return cos(deg * FM_DEG);
}

static double tand(double deg)
{
    return tan(deg * FM_DEG);
}

static double deg(double rad)
{
    return rad / FM_DEG;
}

/* ---- 3.1 time scales ------------------------------------------------------------------------- */

static int is_gregorian(int year, int month, int day)
{
    return year > 1582 || (year == 1582 && (month > 10 || (month == 10 && day >= 15)));
}

double spa_julian_day(int year, int month, double day)
{
    int gregorian = is_gregorian(year, month, (int)floor(day));
    if (month < 3) {
        year -= 1;
        month += 12;
    }
    double jd = floor(365.25 * (year + 4716.0)) + floor(30.6001 * (month + 1)) + day - 1524.5;
    if (gregorian) {
        double a = floor(year / 100.0);
        jd += 2.0 - a + floor(a / 4.0);
    }
    return jd;
}

int spa_date_is_valid(int year, int month, int day)
{
    static const int days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (year < SPA_MIN_YEAR || year > SPA_MAX_YEAR || month < 1 || month > 12 || day < 1)
        return 0;
    if (year == 1582 && month == 10 && day > 4 && day < 15)
        return 0; /* the ten days the Gregorian reform skipped */
    int leap = is_gregorian(year, month, day) ? (year % 4 == 0 && year % 100 != 0) || year % 400 == 0 : year % 4 == 0;
    return day <= days[month - 1] + (month == 2 && leap);
}

/* ---- 3.2 Earth heliocentric position ---------------------------------------------------------- */

/* (sum_i JME^i sum_j A cos(B + C JME)) / 1e8 */
static double earth_series(const spa_series *series, int count, double jme)
{
    double sum = 0.0, power = 1.0;
    for (int i = 0; i < count; i++) {
        double s = 0.0;
        for (int j = 0; j < series[i].count; j++) {
            const double *t = series[i].terms[j];
            s += t[0] * cos(t[1] + t[2] * jme);
        }
        sum += s * power;
        power *= jme;
    }
    return sum / 1e8;
}

/* ---- 3.4 nutation ------------------------------------------------------------------------------ */

static void nutation(spa_state *s)
{
    const double t = s->jce, t2 = t * t, t3 = t2 * t;
    /* mean elongation of the Moon from the Sun, mean anomaly of the Sun, of the Moon, the Moon's
     * argument of latitude, longitude of the ascending node of the Moon's orbit (degrees) */
    s->x_deg[0] = 297.85036 + 445267.111480 * t - 0.0019142 * t2 + t3 / 189474.0;
    s->x_deg[1] = 357.52772 + 35999.050340 * t - 0.0001603 * t2 - t3 / 300000.0;
    s->x_deg[2] = 134.96298 + 477198.867398 * t + 0.0086972 * t2 + t3 / 56250.0;
    s->x_deg[3] = 93.27191 + 483202.017538 * t - 0.0036825 * t2 + t3 / 327270.0;
    s->x_deg[4] = 125.04452 - 1934.136261 * t + 0.0020708 * t2 + t3 / 450000.0;
    double psi = 0.0, eps = 0.0;
    for (int i = 0; i < SPA_NUTATION_COUNT; i++) {
        const spa_nutation_term *n = &spa_nutation_terms[i];
        double arg = 0.0;
        for (int j = 0; j < 5; j++)
            arg += s->x_deg[j] * n->y[j];
        psi += (n->a + n->b * t) * sind(arg);
        eps += (n->c + n->d * t) * cosd(arg);
    }
    /* 0.0001 arcsecond to degrees */
    s->delta_psi_deg = psi / 36000000.0;
    s->delta_epsilon_deg = eps / 36000000.0;
}

/* ---- 3.1-3.10 ---------------------------------------------------------------------------------- */

void spa_geocentric(double jd, double delta_t_s, spa_state *s)
{
    s->jd = jd;
    s->jde = jd + delta_t_s / 86400.0;
    s->jc = (jd - 2451545.0) / 36525.0;
    s->jce = (s->jde - 2451545.0) / 36525.0;
    s->jme = s->jce / 10.0;

    s->l_deg = limit_degrees(deg(earth_series(spa_l_series, SPA_L_COUNT, s->jme)));
    s->b_deg = deg(earth_series(spa_b_series, SPA_B_COUNT, s->jme));
    s->r_au = earth_series(spa_r_series, SPA_R_COUNT, s->jme);

    /* 3.3: seen from the Earth the Sun is opposite */
    s->theta_deg = limit_degrees(s->l_deg + 180.0);
    s->beta_deg = -s->b_deg;

    nutation(s);

    /* 3.5: Laskar's mean obliquity, U in units of 10000 years */
    const double u = s->jme / 10.0;
    static const double eps0[] = {84381.448, -4680.93, -1.55, 1999.25, -51.38, -249.67,
                                  -39.05,    7.12,     27.87, 5.79,    2.45};
    double e0 = 0.0;
    for (int i = 10; i >= 0; i--)
        e0 = e0 * u + eps0[i];
    s->epsilon0_arcsec = e0;
    s->epsilon_deg = e0 / 3600.0 + s->delta_epsilon_deg;

    /* 3.6-3.7: annual aberration, apparent longitude */
    s->aberration_deg = -20.4898 / (3600.0 * s->r_au);
    s->lambda_deg = s->theta_deg + s->delta_psi_deg + s->aberration_deg;

    /* 3.8: sidereal time at Greenwich (UT), apparent = mean + equation of the equinoxes */
    const double jc = s->jc;
    s->nu0_deg = limit_degrees(280.46061837 + 360.98564736629 * (jd - 2451545.0) + 0.000387933 * jc * jc -
                               jc * jc * jc / 38710000.0);
    s->nu_deg = s->nu0_deg + s->delta_psi_deg * cosd(s->epsilon_deg);

    /* 3.9-3.10: ecliptic to equatorial */
    const double lam = s->lambda_deg, eps = s->epsilon_deg, beta = s->beta_deg;
    s->alpha_deg = limit_degrees(deg(atan2(sind(lam) * cosd(eps) - tand(beta) * sind(eps), cosd(lam))));
    s->delta_deg = deg(asin(sind(beta) * cosd(eps) + cosd(beta) * sind(eps) * sind(lam)));
}

/* ---- 3.11-3.15 and A.1 ------------------------------------------------------------------------- */

static double local_hours(const fm_solar_params *p)
{
    return p->hour + p->minute / 60.0 + p->second / 3600.0;
}

void spa_evaluate(const fm_solar_params *p, double delta_t_s, spa_state *s)
{
    double ut_hours = local_hours(p) - p->utc_offset_min / 60.0;
    spa_geocentric(spa_julian_day(p->year, p->month, p->day + ut_hours / 24.0), delta_t_s, s);

    const double phi = p->latitude_deg;
    s->h_deg = limit_degrees(s->nu_deg + p->longitude_deg - s->alpha_deg);

    /* 3.12: parallax of an observer on the reference ellipsoid */
    s->xi_deg = 8.794 / (3600.0 * s->r_au);
    double u = atan(SPA_EARTH_AXIS_RATIO * tand(phi));
    double x = cos(u) + p->elevation_m / SPA_EARTH_RADIUS_M * cosd(phi);
    double y = SPA_EARTH_AXIS_RATIO * sin(u) + p->elevation_m / SPA_EARTH_RADIUS_M * sind(phi);
    double sxi = sind(s->xi_deg), denom = cosd(s->delta_deg) - x * sxi * cosd(s->h_deg);
    s->delta_alpha_deg = deg(atan2(-x * sxi * sind(s->h_deg), denom));
    s->alpha_prime_deg = s->alpha_deg + s->delta_alpha_deg;
    s->delta_prime_deg = deg(atan2((sind(s->delta_deg) - y * sxi) * cosd(s->delta_alpha_deg), denom));
    s->h_prime_deg = s->h_deg - s->delta_alpha_deg;

    /* 3.14: elevation, refraction (pressure in mbar, temperature in C), zenith */
    const double dp = s->delta_prime_deg, hp = s->h_prime_deg;
    s->e0_deg = deg(asin(sind(phi) * sind(dp) + cosd(phi) * cosd(dp) * cosd(hp)));
    s->delta_e_deg = 0.0;
    if (p->refraction && s->e0_deg >= SPA_REFRACTION_LIMIT_DEG)
        s->delta_e_deg = p->pressure_mbar / 1010.0 * 283.0 / (273.0 + p->temperature_c) * 1.02 /
                         (60.0 * tand(s->e0_deg + 10.3 / (s->e0_deg + 5.11)));
    s->e_deg = s->e0_deg + s->delta_e_deg;
    s->zenith_deg = 90.0 - s->e_deg;

    /* 3.15: azimuth, astronomers' (westward from south) and navigators' (eastward from north) */
    s->azimuth_astro_deg = limit_degrees(deg(atan2(sind(hp), cosd(hp) * sind(phi) - tand(dp) * cosd(phi))));
    s->azimuth_deg = limit_degrees(s->azimuth_astro_deg + 180.0);

    /* A.1: equation of time from the Sun's mean longitude M */
    const double m = s->jme;
    double mean_longitude = limit_degrees(280.4664567 + 360007.6982779 * m + 0.03032028 * m * m +
                                          m * m * m / 49931.0 - m * m * m * m / 15300.0 -
                                          m * m * m * m * m / 2000000.0);
    double e_min = 4.0 * (mean_longitude - 0.0057183 - s->alpha_deg + s->delta_psi_deg * cosd(s->epsilon_deg));
    if (e_min > 20.0) /* the difference wraps at 360 degrees = 1440 minutes */
        e_min -= 1440.0 * ceil((e_min - 20.0) / 1440.0);
    else if (e_min < -20.0)
        e_min += 1440.0 * ceil((-20.0 - e_min) / 1440.0);
    s->eot_min = e_min;
}

/* ---- A.2 sunrise, transit, sunset --------------------------------------------------------------- */

/* Quadratic interpolation through v[0], v[1], v[2] at days -1, 0, 1, evaluated at n days;
 * right ascensions are unwrapped across 0/360. */
static double interpolate(const double v[3], double n, int angle)
{
    double a = v[1] - v[0], b = v[2] - v[1];
    if (angle) {
        a = limit_degrees_signed(a);
        b = limit_degrees_signed(b);
    }
    return v[1] + n * (a + b + (b - a) * n) / 2.0;
}

/* Elevation (deg) of the sun at day fraction m of the day that starts at the epoch of sidereal time nu. */
static double elevation_at(double m, double nu, const double alpha[3], const double delta[3], double phi,
                           double sigma, double *hour_angle, double *declination)
{
    double ra = interpolate(alpha, m, 1);
    *declination = interpolate(delta, m, 0);
    *hour_angle = limit_degrees_signed(nu + 360.985647 * m + sigma - ra);
    return deg(asin(sind(phi) * sind(*declination) + cosd(phi) * cosd(*declination) * cosd(*hour_angle)));
}

void spa_rise_transit_set(const fm_solar_params *p, double delta_t_s, fm_solar_position *out)
{
    /* the local date's day starts at local midnight: 0 h local = -offset UT */
    const double jd0 = spa_julian_day(p->year, p->month, p->day) - p->utc_offset_min / 1440.0;
    double alpha[3], delta[3], nu = 0.0;
    for (int k = 0; k < 3; k++) {
        spa_state s;
        spa_geocentric(jd0 + (k - 1), delta_t_s, &s);
        alpha[k] = s.alpha_deg;
        delta[k] = s.delta_deg;
        if (k == 1)
            nu = s.nu_deg;
    }
    const double phi = p->latitude_deg, sigma = p->longitude_deg, h0 = SPA_RISE_SET_ELEVATION_DEG;

    /* transit: the hour angle is zero */
    double m0 = limit_unit((alpha[1] - sigma - nu) / 360.0);
    double hour_angle, dec;
    elevation_at(m0, nu, alpha, delta, phi, sigma, &hour_angle, &dec);
    out->transit_h = 24.0 * limit_unit(m0 - hour_angle / 360.0);

    /* does the centre cross h0 today?  cos H0 = (sin h0 - sin phi sin delta) / (cos phi cos delta),
     * with delta at transit; at a pole (cos phi = 0) only the sign of the numerator counts */
    double num = sind(h0) - sind(phi) * sind(dec), den = cosd(phi) * cosd(dec);
    out->sunrise_h = out->sunset_h = -1.0;
    double cos_h0 = den > 1e-12 ? num / den : (num < 0.0 ? -2.0 : 2.0);
    if (cos_h0 <= -1.0 || cos_h0 >= 1.0) {
        out->daylight = cos_h0 <= -1.0 ? FM_DAYLIGHT_POLAR_DAY : FM_DAYLIGHT_POLAR_NIGHT;
        return;
    }
    out->daylight = FM_DAYLIGHT_NORMAL;
    double h0_hour_angle = deg(acos(cos_h0));
    double m[2] = {limit_unit(m0 - h0_hour_angle / 360.0), limit_unit(m0 + h0_hour_angle / 360.0)};
    double *event[2] = {&out->sunrise_h, &out->sunset_h};
    for (int i = 0; i < 2; i++) {
        /* one Newton step on the elevation: it rises (sets) at 360 cos(delta) cos(phi) sin(H)
         * degrees of elevation per day of hour angle */
        double e = elevation_at(m[i], nu, alpha, delta, phi, sigma, &hour_angle, &dec);
        double mi = m[i] + (e - h0) / (360.0 * cosd(dec) * cosd(phi) * sind(hour_angle));
        *event[i] = 24.0 * limit_unit(mi);
    }
}

/* ---- validation and the public entry ------------------------------------------------------------ */

fm_status spa_validate(const fm_solar_params *p, fm_error *err)
{
    fm_status s;
    if (!spa_date_is_valid(p->year, p->month, p->day))
        return fm_fail_parameter(err, "date", "%04d-%02d-%02d is not a valid calendar date (years %d to %d)", p->year,
                                 p->month, p->day, SPA_MIN_YEAR, SPA_MAX_YEAR);
    if (p->hour < 0 || p->hour > 23 || p->minute < 0 || p->minute > 59 || !(p->second >= 0.0 && p->second < 60.0))
        return fm_fail_parameter(err, "time", "%d:%02d:%02g is not a time of day (00:00:00 to 23:59:59)", p->hour,
                                 p->minute, p->second);
    if ((s = param_check(err, "utc_offset_min", p->utc_offset_min)))
        return s;
    if ((s = param_check(err, "latitude_deg", p->latitude_deg)) ||
        (s = param_check(err, "longitude_deg", p->longitude_deg)) ||
        (s = param_check(err, "elevation_m", p->elevation_m)) ||
        (s = param_check(err, "pressure_mbar", p->pressure_mbar)) ||
        (s = param_check(err, "temperature_c", p->temperature_c)))
        return s;
    if (p->delta_t_s != FM_DELTA_T_ESTIMATE && (s = param_check(err, "delta_t_s", p->delta_t_s)))
        return s;
    return FM_OK;
}

fm_solar_params fm_solar_params_default(void)
{
    return (fm_solar_params){
        .year = 2000,
        .month = 1,
        .day = 1,
        .hour = 12,
        .minute = 0,
        .second = 0.0,
        .utc_offset_min = 0,
        .latitude_deg = 0.0,
        .longitude_deg = 0.0,
        .elevation_m = 0.0,
        .pressure_mbar = 1010.0,
        .temperature_c = 10.0,
        .delta_t_s = FM_DELTA_T_ESTIMATE,
        .refraction = 1,
    };
}

fm_status fm_solar_position_compute(const fm_solar_params *params, fm_solar_position *out, fm_error *err)
{
    fm_status st = spa_validate(params, err);
    if (st)
        return st;
    double dt = params->delta_t_s == FM_DELTA_T_ESTIMATE ? delta_t_estimate_s(params->year, params->month)
                                                         : params->delta_t_s;
    spa_state s;
    spa_evaluate(params, dt, &s);
    out->zenith_deg = s.zenith_deg;
    out->azimuth_deg = s.azimuth_deg;
    out->elevation_deg = s.e_deg;
    out->elevation_true_deg = s.e0_deg;
    out->declination_deg = s.delta_deg;
    out->right_ascension_deg = s.alpha_deg;
    out->earth_sun_distance_au = s.r_au;
    out->equation_of_time_min = s.eot_min;
    out->delta_t_s = dt;
    out->julian_day = s.jd;
    spa_rise_transit_set(params, dt, out);
    return FM_OK;
}

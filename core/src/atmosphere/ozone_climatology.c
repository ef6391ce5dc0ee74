#include "atmosphere/ozone_climatology.h"

#include "base/date.h"
#include "base/param_range.h"
#include "base/status.h"
#include "base/units.h"

#include <math.h>

static double sin_deg(double x)
{
    return sin(x * FM_DEG);
}

double ozone_climatology_column_du(double latitude_deg, double longitude_deg, int day_of_year)
{
    /* wrap into [-180, 180): the I switch below depends on the sign */
    double lon = fmod(longitude_deg + 180.0, 360.0);
    lon = (lon < 0.0 ? lon + 360.0 : lon) - 180.0;
    const double J = 235.0, D = 0.9865, G = 20.0;
    double A, B, C, F, H, I;
    if (latitude_deg >= 0.0) {
        A = 150.0, B = 1.28, C = 40.0, F = -30.0, H = 3.0;
        I = lon >= 0.0 ? 20.0 : 0.0; /* see the header: the reading that gives the published example */
    } else {
        A = 100.0, B = 1.5, C = 30.0, F = 152.625, H = 2.0, I = -75.0;
    }
    double s = sin_deg(B * latitude_deg);
    double e = (double)day_of_year;
    return J + (A + C * sin_deg(D * (e + F)) + G * sin_deg(H * (lon + I))) * s * s;
}

fm_status ozone_climatology_for_date(int year, int month, int day, double latitude_deg, double longitude_deg,
                                     double *column_du, fm_error *err)
{
    if (!date_is_valid(year, month, day))
        return fm_fail_parameter(err, "date", "%04d-%02d-%02d is not a Gregorian date in %d-%d", year, month, day,
                                 FM_DATE_MIN_YEAR, FM_DATE_MAX_YEAR);
    fm_status s;
    if ((s = param_check(err, "latitude_deg", latitude_deg)) || (s = param_check(err, "longitude_deg", longitude_deg)))
        return s;
    *column_du = ozone_climatology_column_du(latitude_deg, longitude_deg, date_day_of_year(year, month, day));
    return FM_OK;
}

/* The sky's sun from a date, time and place, and changing the sun of an existing sky.
 *
 * What in fm_sky depends on the sun's direction (checked field by field in sky.h): only sun_dir
 * and the two parameters that record it.  The atmosphere, aerosol optics and composition do not
 * involve the sun; the column table is per (altitude, view cosine); the sun-transmittance table is
 * tabulated over every sun zenith cosine, so it serves every direction; the sun disk (size, limb
 * darkening) and the solar spectrum depend on the Earth-Sun distance, which a time of day does not
 * change (the distance is the day's).  Everything direction-dependent beyond sun_dir (the adaptive
 * direction grid, single scattering, the ground's diffuse irradiance, the disk drawn into the map)
 * is computed per render from sun_dir and params. */
#include "sky.h"

#include "base/date.h"
#include "base/param_range.h"
#include "base/status.h"
#include "base/units.h"
#include "base/vec.h"
#include "sun/solar_position.h"

#include <math.h>
#include <stddef.h>

static fm_solar_params solar_params_of(const fm_sky_params *p)
{
    fm_solar_params s = fm_solar_params_default();
    s.year = p->year;
    s.month = p->month;
    s.day = p->day;
    s.hour = p->hour;
    s.minute = p->minute;
    s.second = p->second;
    s.utc_offset_min = p->utc_offset_min;
    s.latitude_deg = p->latitude_deg;
    s.longitude_deg = p->longitude_deg;
    /* out-of-range altitudes are reported by the sky's own validation, naming observer_altitude_m */
    s.elevation_m = p->observer_altitude_m >= 0.0 && p->observer_altitude_m <= 100000.0 ? p->observer_altitude_m : 0.0;
    s.pressure_mbar = p->pressure_mbar;
    s.temperature_c = p->temperature_c;
    s.delta_t_s = p->delta_t_s;
    s.refraction = p->refraction;
    return s;
}

static const char *from_time_field(const fm_sky_params *p)
{
    if (p->sun_elevation_deg == FM_SUN_FROM_TIME)
        return "sun_elevation_deg";
    if (p->sun_azimuth_deg == FM_SUN_FROM_TIME)
        return "sun_azimuth_deg";
    if (p->earth_sun_distance_au == FM_SUN_FROM_TIME)
        return "earth_sun_distance_au";
    return NULL;
}

fm_status sky_resolve_sun(const fm_sky_params *in, fm_sky_params *out, fm_solar_position *solar,
                          unsigned *computed, int *has_solar, fm_error *err)
{
    *out = *in;
    *computed = 0;
    *has_solar = 0;
    const char *wanted = from_time_field(in);
    if (in->hour == FM_NO_TIME) {
        if (wanted)
            return fm_fail_parameter(err, wanted, "the sun's position from the time needs a time of day (hour), a "
                                                  "date and a place");
        return FM_OK;
    }
    if (in->year == 0)
        return fm_fail_parameter(err, "hour", "a time of day needs a date (year, month, day) and a place");
    if (!date_is_valid(in->year, in->month, in->day))
        return fm_fail_parameter(err, "date", "%04d-%02d-%02d is not a valid date between %d and %d", in->year,
                                 in->month, in->day, FM_DATE_MIN_YEAR, FM_DATE_MAX_YEAR);
    fm_solar_params sp = solar_params_of(in);
    fm_status s = fm_solar_position_compute(&sp, solar, err);
    if (s)
        return s;
    *has_solar = 1;
    if (in->sun_elevation_deg == FM_SUN_FROM_TIME) {
        out->sun_elevation_deg = solar->elevation_deg;
        *computed |= FM_SUN_COMPUTED_ELEVATION;
    }
    if (in->sun_azimuth_deg == FM_SUN_FROM_TIME) {
        out->sun_azimuth_deg = solar->azimuth_deg;
        *computed |= FM_SUN_COMPUTED_AZIMUTH;
    }
    if (in->earth_sun_distance_au == FM_SUN_FROM_TIME) {
        /* the day's distance, at 12:00 local time: every time of the date shares it (it changes by
         * less than 1.5e-4 AU, 0.03 % of the irradiance, in half a day) */
        fm_solar_position noon;
        sp.hour = 12;
        sp.minute = 0;
        sp.second = 0.0;
        if ((s = fm_solar_position_compute(&sp, &noon, err)))
            return s;
        out->earth_sun_distance_au = noon.earth_sun_distance_au;
        *computed |= FM_SUN_COMPUTED_DISTANCE;
    }
    return FM_OK;
}

static void apply_sun(fm_sky *sky, double elevation_deg, double azimuth_deg)
{
    sky->params.sun_elevation_deg = elevation_deg;
    sky->params.sun_azimuth_deg = azimuth_deg;
    /* exactly as fm_sky_create derives it */
    sky->sun_dir = direction_from_elevation_azimuth(elevation_deg * FM_DEG, azimuth_deg * FM_DEG);
}

fm_status fm_sky_set_sun(fm_sky *sky, double elevation_deg, double azimuth_deg, fm_error *err)
{
    fm_status s;
    if ((s = param_check(err, "sun_elevation_deg", elevation_deg)) ||
        (s = param_check(err, "sun_azimuth_deg", azimuth_deg)))
        return s;
    apply_sun(sky, elevation_deg, azimuth_deg);
    sky->sun_computed &= ~(FM_SUN_COMPUTED_ELEVATION | FM_SUN_COMPUTED_AZIMUTH);
    return FM_OK;
}

fm_status fm_sky_set_time(fm_sky *sky, int hour, int minute, double second, fm_error *err)
{
    if (!sky->has_solar)
        return fm_fail_parameter(err, "hour", "this sky was made without a time of day, date and place");
    fm_sky_params p = sky->params;
    p.hour = hour;
    p.minute = minute;
    p.second = second;
    fm_solar_params sp = solar_params_of(&p);
    fm_solar_position solar;
    fm_status s = fm_solar_position_compute(&sp, &solar, err);
    if (s)
        return s;
    sky->params.hour = hour;
    sky->params.minute = minute;
    sky->params.second = second;
    sky->solar = solar;
    apply_sun(sky, sky->sun_computed & FM_SUN_COMPUTED_ELEVATION ? solar.elevation_deg : p.sun_elevation_deg,
              sky->sun_computed & FM_SUN_COMPUTED_AZIMUTH ? solar.azimuth_deg : p.sun_azimuth_deg);
    return FM_OK;
}

int fm_sky_solar_position(const fm_sky *sky, fm_solar_position *out, unsigned *computed)
{
    if (computed)
        *computed = sky->has_solar ? sky->sun_computed : 0;
    if (!sky->has_solar)
        return 0;
    *out = sky->solar;
    return 1;
}

fm_status fm_sky_params_resolve_sun(const fm_sky_params *params, fm_sky_params *out, fm_error *err)
{
    fm_solar_position solar;
    unsigned computed;
    int has_solar;
    return sky_resolve_sun(params, out, &solar, &computed, &has_solar, err);
}

/* The sky's sun from a date, time and place, and changing the sun of an existing sky.
 *
 * What in fm_sky depends on the sun's direction (checked field by field in sky.h): only sun_dir
 * and the two parameters that record it.  The atmosphere, aerosol optics and composition do not
 * involve the sun; the column table is per (altitude, view cosine); the sun-transmittance table is
 * tabulated over every sun zenith cosine, so it serves every direction; the sun disk (size, limb
 * darkening) and the solar spectrum depend on the Earth-Sun distance, which a time of day does not
 * change (the distance is the date's, with or without a time; 1 AU without a date).  Everything direction-dependent beyond sun_dir (the adaptive
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

/* The sun angle that needs a time of day, or NULL (the distance needs only a date). */
static const char *from_time_field(const fm_sky_params *p)
{
    if (p->sun_elevation_deg == FM_SUN_FROM_TIME)
        return "sun_elevation_deg";
    if (p->sun_azimuth_deg == FM_SUN_FROM_TIME)
        return "sun_azimuth_deg";
    return NULL;
}

/* The Earth-Sun distance of p's date, at 12:00 UT: a function of the date alone (not of the time
 * of day, the UTC offset or Delta T), so that a sky placed by the clock and one placed by the same
 * sun's angles get the same light and the same tables (it changes by less than 1.5e-4 AU, 0.03 % of
 * the irradiance, within a day). */
static fm_status date_distance(const fm_sky_params *p, double *au, fm_error *err)
{
    fm_solar_params sp = fm_solar_params_default();
    sp.year = p->year;
    sp.month = p->month;
    sp.day = p->day;
    sp.hour = 12;
    fm_solar_position noon;
    fm_status s = fm_solar_position_compute(&sp, &noon, err);
    if (!s)
        *au = noon.earth_sun_distance_au;
    return s;
}

static fm_status check_date(const fm_sky_params *p, fm_error *err)
{
    if (!date_is_valid(p->year, p->month, p->day))
        return fm_fail_parameter(err, "date", "%04d-%02d-%02d is not a valid date between %d and %d", p->year,
                                 p->month, p->day, FM_DATE_MIN_YEAR, FM_DATE_MAX_YEAR);
    return FM_OK;
}

/* out's distance when in's is FM_SUN_FROM_TIME: the date's, or the mean (1 AU) without a date. */
static fm_status resolve_distance(const fm_sky_params *in, fm_sky_params *out, unsigned *computed, fm_error *err)
{
    if (in->earth_sun_distance_au != FM_SUN_FROM_TIME)
        return FM_OK;
    if (in->year == 0) {
        out->earth_sun_distance_au = 1.0;
        *computed |= FM_SUN_MEAN_DISTANCE;
        return FM_OK;
    }
    fm_status s = check_date(in, err);
    if (!s && !(s = date_distance(in, &out->earth_sun_distance_au, err)))
        *computed |= FM_SUN_COMPUTED_DISTANCE;
    return s;
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
        return resolve_distance(in, out, computed, err);
    }
    if (in->year == 0)
        return fm_fail_parameter(err, "hour", "a time of day needs a date (year, month, day) and a place");
    fm_solar_params sp = solar_params_of(in);
    fm_status s = check_date(in, err);
    if (s || (s = fm_solar_position_compute(&sp, solar, err)))
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
    return resolve_distance(in, out, computed, err);
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
        *computed = sky->sun_computed;
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

#include "base/param_range.h"

#include "base/status.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* Every numeric parameter the library checks against an interval, by the name its errors give it.
 * Parameters with a sentinel (ozone_column_du, aod550, humidity_percent, wavelength_nm, delta_t_s,
 * reference_samples: FM_... or 0 for "not given") are checked only when given. */
static const fm_param_range ranges[] = {
    {"sun_elevation_deg", -90.0, 90.0, 0, "degrees"},
    {"sun_azimuth_deg", -360.0, 360.0, 0, "degrees"},
    /* ground to aircraft and balloons: higher, the upper limb's light makes the path tracer's
     * estimates heavy-tailed, and the fast path is verified to 20 km */
    {"observer_altitude_m", 0.0, 20000.0, 0, "m"},
    {"ground_albedo", 0.0, 1.0, 0, ""},
    {"ozone_column_du", 0.0, 1000.0, 0, "DU"},
    {"earth_sun_distance_au", 0.95, 1.05, 0, "AU"},
    {"wavelength_nm", 300.0, 1000.0, 0, "nm"},
    {"threads", 0.0, 256.0, 0, ""},
    {"latitude_deg", -90.0, 90.0, 0, "degrees"},
    {"longitude_deg", -180.0, 180.0, 0, "degrees"},
    {"pressure_mbar", 0.0, 2000.0, 0, "mbar"},
    {"temperature_c", -100.0, 100.0, 0, "C"},
    {"delta_t_s", -8000.0, 8000.0, 0, "s"},
    {"utc_offset_min", -720.0, 840.0, 0, "min"}, /* -12:00 to +14:00, the zones in use */
    {"elevation_m", -1000.0, 100000.0, 0, "m"},  /* the solar position's observer (firmament sun) */
    {"turbidity", 0.0, 50.0, 0, ""},
    {"aod550", 0.0, 10.0, 1, ""},
    {"humidity_percent", 0.0, 99.0, 0, "%"},
    /* clouds (docs/clouds.md): optical depths up to the thickest nimbostratus; layers at least two
     * steps of the 50 m profile grid deep, within the troposphere and lower stratosphere */
    {"cloud_tau550", 0.0, 100.0, 1, ""},
    {"cloud_lwp_gm2", 0.0, 1000.0, 1, "g/m^2"},
    {"cloud_base_km", 0.0, 20.0, 0, "km"},
    {"cloud_thickness_km", 0.1, 10.0, 0, "km"},
    {"fog_visibility_m", 10.0, 10000.0, 0, "m"},
    {"width", 8.0, 16384.0, 0, "pixels"},
    {"sample_scale", 0.0, 1024.0, 1, ""},
    {"reference_samples", 1.0, 16777216.0, 0, ""},
    {"camera.fov_deg", 0.0, 170.0, 1, "degrees"},
    {"camera.look_azimuth_deg", -360.0, 360.0, 0, "degrees"},
    {"camera.look_elevation_deg", -90.0, 90.0, 0, "degrees"},
};

const fm_param_range *fm_param_range_of(const char *field)
{
    for (size_t i = 0; i < sizeof ranges / sizeof ranges[0]; i++)
        if (strcmp(ranges[i].field, field) == 0)
            return &ranges[i];
    return NULL;
}

void param_range_format(const fm_param_range *r, char *out, size_t size)
{
    snprintf(out, size, "%c%g, %g]%s%s", r->min_open ? '(' : '[', r->min, r->max, r->unit[0] ? " " : "", r->unit);
}

fm_status param_check(fm_error *err, const char *field, double v)
{
    const fm_param_range *r = fm_param_range_of(field);
    assert(r != NULL);
    if (isfinite(v) && (r->min_open ? v > r->min : v >= r->min) && v <= r->max)
        return FM_OK;
    char range[64];
    param_range_format(r, range, sizeof range);
    return fm_fail_parameter(err, field, "%g is outside %s", v, range);
}

#!/usr/bin/python3
"""Independent reference values for tests/physics/test_solar_position.c, from PyEphem (libastro:
VSOP87 Earth theory, IAU 1980 nutation; Debian package python3-ephem 4.1.4).  Not part of the build:
run it to regenerate the table printed into the test.

For each case (local date and time, UTC offset, place): PyEphem's topocentric apparent elevation
without refraction (pressure 0) and azimuth at the instant, and the local times of sunrise, transit
and sunset of the local date with the sun's centre at -0.8333 degrees (SPA's convention), plus the
Delta T PyEphem used (the test gives SPA the same Delta T, so that the comparison is of the
algorithms, not of two Delta T models)."""
import math

import ephem

# name, y, m, d, hh, mm, ss, utc offset (min), latitude, longitude (east +), elevation (m)
CASES = [
    ("Golden CO (SPA's example place)", 2003, 10, 17, 12, 30, 30, -420, 39.742476, -105.1786, 1830.14),
    ("Sydney, southern summer morning", 2023, 1, 15, 9, 0, 0, 660, -33.8688, 151.2093, 58.0),
    ("Singapore, equinox noon, tropics", 2023, 3, 21, 13, 5, 0, 480, 1.3521, 103.8198, 15.0),
    ("Honolulu, sun north of the zenith", 2021, 7, 4, 12, 30, 0, -600, 21.3069, -157.8583, 5.0),
    ("Cape Town, southern winter afternoon", 2022, 6, 21, 16, 30, 0, 120, -33.9249, 18.4241, 10.0),
    ("Quito at 2850 m, September", 2020, 9, 22, 7, 15, 0, -300, -0.1807, -78.4678, 2850.0),
    ("Tokyo, New Year's Eve afternoon", 1995, 12, 31, 15, 45, 0, 540, 35.6762, 139.6503, 40.0),
    ("Greenwich, 1905", 1905, 5, 5, 10, 0, 0, 0, 51.4769, -0.0005, 46.0),
    ("New York, 2099", 2099, 11, 11, 8, 0, 0, -300, 40.7128, -74.0060, 10.0),
    ("Auckland, early morning across the UT date", 2024, 2, 29, 6, 40, 0, 780, -36.8485, 174.7633, 20.0),
    ("Longyearbyen, midnight sun", 2023, 6, 21, 0, 30, 0, 120, 78.2232, 15.6267, 10.0),
    ("Longyearbyen, polar night noon", 2023, 12, 21, 12, 0, 0, 60, 78.2232, 15.6267, 10.0),
    ("McMurdo, southern polar day", 2024, 1, 1, 3, 0, 0, 780, -77.8419, 166.6863, 10.0),
]


def local_hours(d, midnight):
    """Hours of the event d after local midnight."""
    return (d - midnight) * 24.0


def main():
    for name, y, mo, d, hh, mi, ss, off, lat, lon, elev in CASES:
        o = ephem.Observer()
        o.lat, o.lon, o.elevation = str(lat), str(lon), elev
        o.pressure = 0
        o.horizon = str(-0.8333)
        midnight = ephem.Date(ephem.Date((y, mo, d, 0, 0, 0)) - off * ephem.minute)
        o.date = ephem.Date(midnight + (hh * 3600 + mi * 60 + ss) * ephem.second)
        sun = ephem.Sun()
        sun.compute(o)
        alt, az = math.degrees(sun.alt), math.degrees(sun.az)  # before the searches recompute sun
        dt = ephem.delta_t(o.date)
        o.date = midnight
        try:
            rise = local_hours(o.next_rising(sun, use_center=True), midnight)
            sset = local_hours(o.next_setting(sun, use_center=True), midnight)
            day = "FM_DAYLIGHT_NORMAL"
        except ephem.AlwaysUpError:
            rise = sset = -1.0
            day = "FM_DAYLIGHT_POLAR_DAY"
        except ephem.NeverUpError:
            rise = sset = -1.0
            day = "FM_DAYLIGHT_POLAR_NIGHT"
        o.date = midnight
        transit = local_hours(o.next_transit(sun), midnight)
        print('    {"%s", %d, %d, %d, %d, %d, %d, %d, %.6f, %.6f, %.2f, %.4f, %.6f, %.6f, %.5f, %.5f, %.5f, %s},'
              % (name, y, mo, d, hh, mi, ss, off, lat, lon, elev, dt, alt, az,
                 rise, transit, sset, day))


if __name__ == "__main__":
    main()

/* Ozone by date and place: the van Heuklon (1979) total column against its published example and
 * an independent evaluation of the formula, and the six AFGL profiles (columns as tabulated,
 * normalisation, effective temperatures, choice by latitude and season). */
#include "check.h"

#include "atmosphere/ozone.h"
#include "atmosphere/ozone_climatology.h"
#include "atmosphere/ozone_profile.h"
#include "base/units.h"
#include "data/tables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The fit written out again from PHYSICS.md section 4.2 (radians here, coefficients per
 * hemisphere, northern I = 20 east of Greenwich and 0 west of it). */
static double van_heuklon(double lat, double lon_east, double day)
{
    static const double north[9] = {150, 1.28, 40, 0.9865, -30, 20, 3, 20, 235};
    static const double south[9] = {100, 1.5, 30, 0.9865, 152.625, 20, 2, -75, 235};
    const double *k = lat > 0.0 ? north : south;
    double i = k[7];
    if (lat > 0.0 && lon_east < 0.0)
        i = 0.0;
    const double r = FM_PI / 180.0;
    double seasonal = k[2] * sin(r * k[3] * (day + k[4]));
    double wave = k[5] * sin(r * k[6] * (lon_east + i));
    return k[8] + (k[0] + seasonal + wave) * pow(sin(r * k[1] * lat), 2);
}

static void van_heuklon_check_values(void **state)
{
    /* 235 DU at the equator whatever the day and longitude */
    for (int day = 1; day <= 366; day += 73)
        for (double lon = -180.0; lon <= 180.0; lon += 45.0)
            if (fabs(ozone_climatology_column_du(0.0, lon, day) - 235.0) > 1e-9)
                fail_msg("equator, %g E, day %d: %.6f DU", lon, day, ozone_climatology_column_du(0.0, lon, day));
    /* published example of the MATLAB ozone_ (Broenkow & Flora 1997): 36 N, 122 W, day 185 */
    double sf = ozone_climatology_column_du(36.0, -122.0, 185);
    print_message("36 N 122 W day 185: %.2f DU (published 321.2)\n", sf);
    check_abs(sf, 321.2, 0.05, "van Heuklon 36 N 122 W day 185");
    /* 4 July 1979 is day 185 */
    double by_date = 0.0;
    fm_error err = {0};
    assert_int_equal(ozone_climatology_for_date(1979, 7, 4, 36.0, -122.0, &by_date, &err), FM_OK);
    check_abs(by_date, sf, 1e-12, "same example from the calendar date");
    /* more values from the independent evaluation: southern spring (Sydney, 15 October), high
     * latitudes in both hemispheres, western and eastern northern longitudes */
    const struct {
        double lat, lon;
        int day;
    } c[] = {
        {-33.9, 151.2, 288}, {70.0, 20.0, 80}, {-70.0, -60.0, 280}, {45.0, -90.0, 30},
        {45.0, 90.0, 30},    {51.5, -0.1, 100}, {-1.3, 36.8, 100},  {-89.0, 0.0, 1},
    };
    for (size_t n = 0; n < sizeof c / sizeof c[0]; n++) {
        double got = ozone_climatology_column_du(c[n].lat, c[n].lon, c[n].day);
        double want = van_heuklon(c[n].lat, c[n].lon, c[n].day);
        print_message("%6.1f %7.1f day %3d: %.2f DU\n", c[n].lat, c[n].lon, c[n].day, got);
        check_abs(got, want, 1e-9, "van Heuklon vs independent evaluation");
    }
    /* longitude wraps: 190 E is 170 W */
    check_abs(ozone_climatology_column_du(50.0, 190.0, 40), ozone_climatology_column_du(50.0, -170.0, 40), 1e-9,
              "longitude wrap");
    /* out-of-range dates and places are errors naming the field */
    assert_int_equal(ozone_climatology_for_date(2023, 2, 30, 0.0, 0.0, &by_date, &err), FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "date"));
    assert_int_equal(ozone_climatology_for_date(2024, 2, 29, 91.0, 0.0, &by_date, &err), FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "latitude_deg"));
    assert_int_equal(ozone_climatology_for_date(2024, 2, 29, 0.0, -180.5, &by_date, &err), FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "longitude_deg"));
}

/* The seasonal term peaks in each hemisphere's spring: 1 May (day 121) in the north, end of
 * October in the south; the amplitude is C sin^2(B phi). */
static void seasonal_cycle_peaks_in_spring(void **state)
{
    int best_n = 0, best_s = 0;
    double max_n = -1.0, min_n = 1e9, max_s = -1.0;
    for (int day = 1; day <= 365; day++) {
        double n = ozone_climatology_column_du(60.0, 10.0, day), s = ozone_climatology_column_du(-60.0, 10.0, day);
        if (n > max_n)
            max_n = n, best_n = day;
        min_n = fmin(min_n, n);
        if (s > max_s)
            max_s = s, best_s = day;
    }
    print_message("60 N: maximum %.1f DU on day %d; 60 S: %.1f DU on day %d\n", max_n, best_n, max_s, best_s);
    assert_true(best_n >= 60 && best_n <= 151); /* March-May */
    assert_true(abs(best_n - 121) <= 1);
    assert_true(best_s >= 244 && best_s <= 334); /* September-November */
    double s2 = pow(sin(1.28 * 60.0 * FM_PI / 180.0), 2);
    check_abs(max_n - min_n, 2.0 * 40.0 * s2, 0.05, "northern seasonal amplitude at 60 N");
}

/* Tabulated density, log-linear between the levels, written again here. */
static double table_density(const double (*lv)[3], double z_km)
{
    int i = 0;
    while (i < FM_AFGL_LEVEL_COUNT - 2 && lv[i + 1][0] <= z_km)
        i++;
    double t = (z_km - lv[i][0]) / (lv[i + 1][0] - lv[i][0]);
    return exp((1.0 - t) * log(lv[i][2]) + t * log(lv[i + 1][2]));
}

static void tabulated_columns_match_physics_md(void **state)
{
    /* PHYSICS.md section 4.2: columns of the raw AFGL tables */
    const double expect_du[OZONE_PROFILE_COUNT] = {344.0, 282.0, 334.0, 378.0, 348.0, 376.0};
    for (int p = 0; p < OZONE_PROFILE_COUNT; p++) {
        const double(*lv)[3] = fm_afgl_profiles[p];
        /* composite Simpson in each layer, 0-100 km */
        double col = 0.0;
        for (int i = 0; i + 1 < FM_AFGL_LEVEL_COUNT && lv[i][0] < 100.0; i++) {
            const int m = 64;
            double a = lv[i][0], b = fmin(lv[i + 1][0], 100.0), h = (b - a) / m, s = 0.0;
            for (int j = 0; j <= m; j++)
                s += (j == 0 || j == m ? 1.0 : (j % 2 ? 4.0 : 2.0)) * table_density(lv, a + j * h);
            col += s * h / 3.0 * FM_KM;
        }
        double du = col / FM_DU_MOLECULES_PER_M2;
        print_message("%-20s %.1f DU as tabulated\n", ozone_profile_name((ozone_profile)p), du);
        check_rel(du, expect_du[p], 0.01, "AFGL column vs PHYSICS.md 4.2");
        check_rel(ozone_profile_tabulated_column_du((ozone_profile)p), du, 1e-4, "library's tabulated column");
    }
}

static void profiles_integrate_to_one_du(void **state)
{
    for (int p = 0; p < OZONE_PROFILE_COUNT; p++) {
        /* composite Simpson over 0-100 km in 10 m steps (the levels fall on the nodes) */
        const int m = 10000;
        const double h = FM_ATMOSPHERE_HEIGHT_M / m;
        double s = 0.0, best = 0.0, z_best = 0.0;
        for (int j = 0; j <= m; j++) {
            double n = ozone_profile_density_per_du((ozone_profile)p, j * h);
            s += (j == 0 || j == m ? 1.0 : (j % 2 ? 4.0 : 2.0)) * n;
            if (n > best)
                best = n, z_best = j * h;
        }
        double du = s * h / 3.0 / FM_DU_MOLECULES_PER_M2;
        check_abs(du, 1.0, 1e-3, "normalised profile column (DU)");
        /* every profile peaks in the 15-30 km ozone layer */
        print_message("%-20s peak at %.1f km\n", ozone_profile_name((ozone_profile)p), z_best / FM_KM);
        assert_true(z_best >= 15000.0 && z_best <= 30000.0);
    }
    /* the U.S. Standard functions of ozone.h are this module's U.S. Standard case */
    for (double z = 0.0; z <= 100000.0; z += 777.0)
        assert_true(ozone_number_density_per_du(z) == ozone_profile_density_per_du(OZONE_PROFILE_US_STANDARD, z));
    assert_true(ozone_profile_density_per_du(OZONE_PROFILE_COUNT, 20000.0) == 0.0);
}

static void effective_temperatures(void **state)
{
    double t_eff[OZONE_PROFILE_COUNT];
    for (int p = 0; p < OZONE_PROFILE_COUNT; p++) {
        t_eff[p] = ozone_profile_effective_temperature_k((ozone_profile)p);
        /* independent: trapezoid over 50 m steps of n(z) T(z) with the table's own levels */
        const double(*lv)[3] = fm_afgl_profiles[p];
        double num = 0.0, den = 0.0;
        for (double z = 0.0; z <= 100.0; z += 0.05) {
            int i = 0;
            while (i < FM_AFGL_LEVEL_COUNT - 2 && lv[i + 1][0] <= z)
                i++;
            double t = (z - lv[i][0]) / (lv[i + 1][0] - lv[i][0]);
            double temp = lv[i][1] + t * (lv[i + 1][1] - lv[i][1]);
            double n = table_density(lv, z) * (z == 0.0 || z > 99.97 ? 0.5 : 1.0);
            num += n * temp;
            den += n;
        }
        print_message("%-20s T_eff %.2f K\n", ozone_profile_name((ozone_profile)p), t_eff[p]);
        check_abs(t_eff[p], num / den, 0.05, "ozone-weighted temperature");
        assert_true(t_eff[p] > 200.0 && t_eff[p] < 240.0);
    }
    /* the warm tropical stratosphere against the cold polar-night one */
    assert_true(t_eff[OZONE_PROFILE_TROPICAL] - t_eff[OZONE_PROFILE_SUBARCTIC_WINTER] > 5.0);
    assert_true(t_eff[OZONE_PROFILE_MIDLATITUDE_SUMMER] > t_eff[OZONE_PROFILE_MIDLATITUDE_WINTER]);
    check_abs(ozone_effective_temperature_k(), t_eff[OZONE_PROFILE_US_STANDARD], 1e-12, "ozone.h wrapper");
}

static void profile_by_latitude_and_season(void **state)
{
    const struct {
        double lat;
        int day;
        ozone_profile want;
    } c[] = {
        {0.0, 1, OZONE_PROFILE_TROPICAL},
        {22.9, 196, OZONE_PROFILE_TROPICAL},
        {-22.9, 15, OZONE_PROFILE_TROPICAL},
        {23.0, 196, OZONE_PROFILE_MIDLATITUDE_SUMMER},
        {45.0, 196, OZONE_PROFILE_MIDLATITUDE_SUMMER},
        {45.0, 15, OZONE_PROFILE_MIDLATITUDE_WINTER},
        {-45.0, 196, OZONE_PROFILE_MIDLATITUDE_WINTER},
        {-45.0, 15, OZONE_PROFILE_MIDLATITUDE_SUMMER},
        {60.0, 196, OZONE_PROFILE_MIDLATITUDE_SUMMER},
        {60.1, 196, OZONE_PROFILE_SUBARCTIC_SUMMER},
        {70.0, 15, OZONE_PROFILE_SUBARCTIC_WINTER},
        {-70.0, 196, OZONE_PROFILE_SUBARCTIC_WINTER},
        {-70.0, 15, OZONE_PROFILE_SUBARCTIC_SUMMER},
        {90.0, 366, OZONE_PROFILE_SUBARCTIC_WINTER},
        /* season edges: summer is days 106-287, nearer 15 July than 15 January */
        {45.0, 105, OZONE_PROFILE_MIDLATITUDE_WINTER},
        {45.0, 106, OZONE_PROFILE_MIDLATITUDE_SUMMER},
        {45.0, 287, OZONE_PROFILE_MIDLATITUDE_SUMMER},
        {45.0, 288, OZONE_PROFILE_MIDLATITUDE_WINTER},
        {-45.0, 105, OZONE_PROFILE_MIDLATITUDE_SUMMER},
        {-45.0, 288, OZONE_PROFILE_MIDLATITUDE_SUMMER},
    };
    for (size_t n = 0; n < sizeof c / sizeof c[0]; n++) {
        ozone_profile got = ozone_profile_for(c[n].lat, c[n].day);
        if (got != c[n].want)
            fail_msg("latitude %g, day %d: %s, expected %s", c[n].lat, c[n].day, ozone_profile_name(got),
                     ozone_profile_name(c[n].want));
    }
    /* the season switch matches the definition: nearer (round the year) to day 196 than to day 15 */
    for (int day = 1; day <= 365; day++) {
        int to_july = abs(day - 196), to_jan = abs(day - 15);
        to_jan = to_jan < 365 - to_jan ? to_jan : 365 - to_jan;
        int summer = to_july < to_jan;
        assert_int_equal(ozone_profile_for(45.0, day) == OZONE_PROFILE_MIDLATITUDE_SUMMER, summer);
        assert_int_equal(ozone_profile_for(-75.0, day) == OZONE_PROFILE_SUBARCTIC_SUMMER, !summer);
    }
    for (int p = 0; p < OZONE_PROFILE_COUNT; p++)
        for (int q = 0; q < p; q++)
            assert_string_not_equal(ozone_profile_name((ozone_profile)p), ozone_profile_name((ozone_profile)q));
    assert_null(ozone_profile_name(OZONE_PROFILE_COUNT));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(van_heuklon_check_values),
        cmocka_unit_test(seasonal_cycle_peaks_in_spring),
        cmocka_unit_test(tabulated_columns_match_physics_md),
        cmocka_unit_test(profiles_integrate_to_one_du),
        cmocka_unit_test(effective_temperatures),
        cmocka_unit_test(profile_by_latitude_and_season),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

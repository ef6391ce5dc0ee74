/* Gregorian calendar: leap years, validity, day of year against an independent Julian day number. */
#include "check.h"

#include "base/date.h"

/* Julian day number of a Gregorian date (Fliegel & Van Flandern 1968, integer arithmetic). */
static long julian_day_number(long y, long m, long d)
{
    long a = (m - 14) / 12;
    return (1461 * (y + 4800 + a)) / 4 + (367 * (m - 2 - 12 * a)) / 12 - (3 * ((y + 4900 + a) / 100)) / 4 + d - 32075;
}

static void leap_years_and_validity(void **state)
{
    assert_true(date_is_leap_year(2024));
    assert_true(date_is_leap_year(2000));
    assert_false(date_is_leap_year(1900));
    assert_false(date_is_leap_year(2100));
    assert_false(date_is_leap_year(2023));

    assert_false(date_is_valid(2023, 2, 30));
    assert_false(date_is_valid(2023, 2, 29));
    assert_true(date_is_valid(2024, 2, 29));
    assert_true(date_is_valid(2000, 2, 29));
    assert_false(date_is_valid(1900, 2, 29));
    assert_false(date_is_valid(2100, 2, 29));
    assert_true(date_is_valid(1900, 1, 1));
    assert_true(date_is_valid(2100, 12, 31));
    assert_false(date_is_valid(1899, 12, 31));
    assert_false(date_is_valid(2101, 1, 1));
    assert_false(date_is_valid(2024, 0, 1));
    assert_false(date_is_valid(2024, 13, 1));
    assert_false(date_is_valid(2024, 1, 0));
    assert_false(date_is_valid(2024, 1, 32));
    assert_false(date_is_valid(2024, 4, 31));
    assert_true(date_is_valid(2024, 4, 30));
    assert_int_equal(date_day_of_year(2023, 2, 30), 0);
}

static void day_of_year_matches_julian_day_numbers(void **state)
{
    assert_int_equal(date_day_of_year(2023, 1, 1), 1);
    assert_int_equal(date_day_of_year(2023, 12, 31), 365);
    assert_int_equal(date_day_of_year(2024, 12, 31), 366);
    assert_int_equal(date_day_of_year(2024, 3, 1), 61);
    assert_int_equal(date_day_of_year(2023, 3, 1), 60);
    assert_int_equal(date_day_of_year(1979, 7, 4), 185);
    /* every day of 1900-2100: the day of year counts from the year's 1 January, and the valid days
     * of a year are exactly the days between two New Year's Days */
    for (int y = FM_DATE_MIN_YEAR; y <= FM_DATE_MAX_YEAR; y++) {
        long jan1 = julian_day_number(y, 1, 1);
        int valid = 0;
        for (int m = 1; m <= 12; m++)
            for (int d = 1; d <= 31; d++) {
                if (!date_is_valid(y, m, d))
                    continue;
                valid++;
                long expect = julian_day_number(y, m, d) - jan1 + 1;
                if (date_day_of_year(y, m, d) != expect)
                    fail_msg("%04d-%02d-%02d: day %d, expected %ld", y, m, d, date_day_of_year(y, m, d), expect);
            }
        assert_int_equal(valid, julian_day_number(y + 1, 1, 1) - jan1);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(leap_years_and_validity),
        cmocka_unit_test(day_of_year_matches_julian_day_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

#include "base/date.h"

int date_is_leap_year(int year)
{
    return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

int date_days_in_month(int year, int month)
{
    static const int days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (month < 1 || month > 12)
        return 0;
    return days[month - 1] + (month == 2 && date_is_leap_year(year));
}

int date_is_valid(int year, int month, int day)
{
    return year >= FM_DATE_MIN_YEAR && year <= FM_DATE_MAX_YEAR && day >= 1 && day <= date_days_in_month(year, month);
}

int date_day_of_year(int year, int month, int day)
{
    if (!date_is_valid(year, month, day))
        return 0;
    int doy = day;
    for (int m = 1; m < month; m++)
        doy += date_days_in_month(year, m);
    return doy;
}

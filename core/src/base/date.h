/* Gregorian calendar dates for the years the sky parameters accept (1900-2100): validity and day
 * of year.  Leap years follow the Gregorian rule (every 4th year, except centuries not divisible
 * by 400), so 1900 and 2100 are common years and 2000 is a leap year. */
#ifndef FM_BASE_DATE_H
#define FM_BASE_DATE_H

#define FM_DATE_MIN_YEAR 1900
#define FM_DATE_MAX_YEAR 2100

/* 1 if year (any Gregorian year) is a leap year, else 0. */
int date_is_leap_year(int year);

/* Days in month (1-12) of year; 0 if month is out of range. */
int date_days_in_month(int year, int month);

/* 1 if (year, month, day) is a real date with year in [FM_DATE_MIN_YEAR, FM_DATE_MAX_YEAR], else 0. */
int date_is_valid(int year, int month, int day);

/* Day of year, 1 (1 January) to 365 or 366 (31 December of a leap year); 0 for an invalid date. */
int date_day_of_year(int year, int month, int day);

#endif

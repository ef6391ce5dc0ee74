/* Command-line values for dates, times of day and UTC offsets, shared by `firmament render` and
 * `firmament sun`.  Each parser returns 1 on success; on failure 0 with one line in msg that starts
 * with the flag and names the problem ("--time: '25:00': hour 25 is outside 00-23"). */
#ifndef FM_CLI_TIME_ARGS_H
#define FM_CLI_TIME_ARGS_H

#include <stddef.h>

/* YYYY-MM-DD (the calendar check is the library's). */
int parse_date_arg(const char *flag, const char *arg, int *year, int *month, int *day, char *msg, size_t msg_size);

/* HH:MM or HH:MM:SS, 00:00:00 to 23:59:59; *seconds_of_day = 3600 h + 60 m + s. */
int parse_time_arg(const char *flag, const char *arg, int *seconds_of_day, char *msg, size_t msg_size);

/* +HH, -HH, +HH:MM, -HH:MM (also H or HH:MM without a sign, Z for 0), -12:00 to +14:00. */
int parse_utc_offset_arg(const char *flag, const char *arg, int *minutes, char *msg, size_t msg_size);

/* on | off */
int parse_on_off_arg(const char *flag, const char *arg, int *on, char *msg, size_t msg_size);

/* "HH:MM:SS" of a time of day in seconds (taken modulo one day), into buf (at least 9 bytes). */
void format_time_of_day(int seconds_of_day, char *buf, size_t size);

/* "+HH:MM" / "-HH:MM" of an offset in minutes, into buf (at least 7 bytes). */
void format_utc_offset(int minutes, char *buf, size_t size);

#endif

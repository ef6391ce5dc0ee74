#include "time_args.h"

#include "firmament/firmament.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

/* n_min to n_max decimal digits at *s (no sign, no spaces); advances *s. */
static int digits(const char **s, int n_min, int n_max, int *value)
{
    int n = 0, v = 0;
    while (n < n_max && isdigit((unsigned char)(*s)[n])) {
        v = 10 * v + ((*s)[n] - '0');
        n++;
    }
    if (n < n_min)
        return 0;
    *s += n;
    *value = v;
    return 1;
}

int parse_date_arg(const char *flag, const char *arg, int *year, int *month, int *day, char *msg, size_t msg_size)
{
    const char *s = arg;
    int y, m, d;
    if (!digits(&s, 4, 4, &y) || *s++ != '-' || !digits(&s, 2, 2, &m) || *s++ != '-' || !digits(&s, 2, 2, &d) ||
        *s != '\0') {
        snprintf(msg, msg_size, "%s: '%s' is not a date YYYY-MM-DD", flag, arg);
        return 0;
    }
    *year = y;
    *month = m;
    *day = d;
    return 1;
}

int parse_time_arg(const char *flag, const char *arg, int *seconds_of_day, char *msg, size_t msg_size)
{
    const char *s = arg;
    int h, m, sec = 0;
    if (!digits(&s, 1, 2, &h) || *s++ != ':' || !digits(&s, 2, 2, &m) ||
        (*s == ':' && (s++, !digits(&s, 2, 2, &sec))) || *s != '\0') {
        snprintf(msg, msg_size, "%s: '%s' is not a time HH:MM or HH:MM:SS", flag, arg);
        return 0;
    }
    if (h > 23) {
        snprintf(msg, msg_size, "%s: '%s': hour %d is outside 00-23", flag, arg, h);
        return 0;
    }
    if (m > 59) {
        snprintf(msg, msg_size, "%s: '%s': minute %d is outside 00-59", flag, arg, m);
        return 0;
    }
    if (sec > 59) {
        snprintf(msg, msg_size, "%s: '%s': second %d is outside 00-59", flag, arg, sec);
        return 0;
    }
    *seconds_of_day = 3600 * h + 60 * m + sec;
    return 1;
}

int parse_utc_offset_arg(const char *flag, const char *arg, int *minutes, char *msg, size_t msg_size)
{
    const char *s = arg;
    int sign = 1, h, m = 0;
    if (strcmp(arg, "Z") == 0) {
        *minutes = 0;
        return 1;
    }
    if (*s == '+' || *s == '-')
        sign = *s++ == '-' ? -1 : 1;
    if (!digits(&s, 1, 2, &h) || (*s == ':' && (s++, !digits(&s, 2, 2, &m))) || *s != '\0') {
        snprintf(msg, msg_size, "%s: '%s' is not a UTC offset +HH[:MM] or -HH[:MM]", flag, arg);
        return 0;
    }
    int total = sign * (60 * h + m);
    const fm_param_range *r = fm_param_range_of("utc_offset_min");
    if (m > 59 || total < r->min || total > r->max) {
        snprintf(msg, msg_size, "%s: '%s' is outside -12:00 to +14:00", flag, arg);
        return 0;
    }
    *minutes = total;
    return 1;
}

int parse_on_off_arg(const char *flag, const char *arg, int *on, char *msg, size_t msg_size)
{
    if (strcmp(arg, "on") == 0 || strcmp(arg, "off") == 0) {
        *on = arg[1] == 'n';
        return 1;
    }
    snprintf(msg, msg_size, "%s: '%s' is not one of on, off", flag, arg);
    return 0;
}

void format_time_of_day(int seconds_of_day, char *buf, size_t size)
{
    int t = ((seconds_of_day % 86400) + 86400) % 86400;
    snprintf(buf, size, "%02d:%02d:%02d", t / 3600, t / 60 % 60, t % 60);
}

void format_utc_offset(int minutes, char *buf, size_t size)
{
    int a = minutes < 0 ? -minutes : minutes;
    snprintf(buf, size, "%c%02d:%02d", minutes < 0 ? '-' : '+', a / 60 % 100, a % 60);
}

#include "numbers.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>

static const char *skip_digits(const char *p, int *count)
{
    while (isdigit((unsigned char)*p)) {
        p++;
        (*count)++;
    }
    return p;
}

/* Whether s is written as the header says (whole: no fraction or exponent). */
static int decimal_syntax(const char *s, int whole)
{
    const char *p = s;
    int digits = 0;
    if (*p == '+' || *p == '-')
        p++;
    p = skip_digits(p, &digits);
    if (!whole && *p == '.')
        p = skip_digits(p + 1, &digits);
    if (!digits)
        return 0;
    if (!whole && (*p == 'e' || *p == 'E')) {
        int exponent = 0;
        p++;
        if (*p == '+' || *p == '-')
            p++;
        p = skip_digits(p, &exponent);
        if (!exponent)
            return 0;
    }
    return *p == '\0';
}

int parse_decimal(const char *s, double *out)
{
    if (!decimal_syntax(s, 0))
        return 0;
    errno = 0;
    double v = strtod(s, NULL);
    if (errno == ERANGE || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

int parse_whole(const char *s, long long lo, long long hi, long long *out)
{
    if (!decimal_syntax(s, 1))
        return 0;
    errno = 0;
    long long v = strtoll(s, NULL, 10);
    if (errno == ERANGE || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

/* Numbers on the command line, as people write them: [+-]digits[.digits][e[+-]digits] (a whole number
 * without the fraction and exponent).  strtod and strtoll alone also take leading spaces,
 * hexadecimal ("0x10" as 16) and, for strtod, "inf" and "nan", none of which a user means. */
#ifndef FM_CLI_NUMBERS_H
#define FM_CLI_NUMBERS_H

/* A finite decimal number: 1 with *out set, else 0. */
int parse_decimal(const char *s, double *out);

/* A whole number within [lo, hi]: 1 with *out set, else 0. */
int parse_whole(const char *s, long long lo, long long hi, long long *out);

#endif

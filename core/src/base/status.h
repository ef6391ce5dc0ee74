/* Error reporting inside the library: fill the caller's fm_error with one line and return the code.
 * Nothing here prints or exits; only the executable does. */
#ifndef FM_BASE_STATUS_H
#define FM_BASE_STATUS_H

#include "firmament/firmament.h"

#if defined(__MINGW32__) /* its C99 printf (__USE_MINGW_ANSI_STDIO), not msvcrt's */
#define FM_PRINTF(a, b) __attribute__((format(gnu_printf, a, b)))
#elif defined(__GNUC__)
#define FM_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define FM_PRINTF(a, b)
#endif

/* Formats the message into err (if not NULL) and returns code. */
fm_status fm_fail(fm_error *err, fm_status code, const char *fmt, ...) FM_PRINTF(3, 4);

/* Like fm_fail, for a parameter out of range: records the field name and prefixes the message with
 * it ("<field>: ..."). */
fm_status fm_fail_parameter(fm_error *err, const char *field, const char *fmt, ...) FM_PRINTF(3, 4);

#endif

#include "base/status.h"

#include <stdarg.h>
#include <stdio.h>

/* One list gives each code its name. */
#define FM_STATUS_LIST(X)                        \
    X(FM_OK, "ok")                               \
    X(FM_ERR_INVALID_ARGUMENT, "invalid argument") \
    X(FM_ERR_IO, "input/output error")           \
    X(FM_ERR_OUT_OF_MEMORY, "out of memory")     \
    X(FM_ERR_CANCELLED, "cancelled")             \
    X(FM_ERR_INTERNAL, "internal error")

const char *fm_status_name(fm_status status)
{
    switch (status) {
#define FM_STATUS_CASE(code, name) \
    case code:                     \
        return name;
        FM_STATUS_LIST(FM_STATUS_CASE)
#undef FM_STATUS_CASE
    }
    return "unknown status";
}

fm_status fm_fail(fm_error *err, fm_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        err->status = code;
        err->parameter[0] = '\0';
    }
    return code;
}

fm_status fm_fail_parameter(fm_error *err, const char *field, const char *fmt, ...)
{
    if (err) {
        int n = snprintf(err->message, sizeof err->message, "%s: ", field);
        va_list ap;
        va_start(ap, fmt);
        if (n > 0 && (size_t)n < sizeof err->message)
            vsnprintf(err->message + n, sizeof err->message - (size_t)n, fmt, ap);
        va_end(ap);
        snprintf(err->parameter, sizeof err->parameter, "%s", field);
        err->status = FM_ERR_INVALID_ARGUMENT;
    }
    return FM_ERR_INVALID_ARGUMENT;
}

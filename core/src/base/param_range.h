/* The ranges of the library's numeric parameters (fm_param_range, firmament.h): validation checks
 * values against them here, so that the message, the preset reader and the executable's options
 * all read one table. */
#ifndef FM_BASE_PARAM_RANGE_H
#define FM_BASE_PARAM_RANGE_H

#include "firmament/firmament.h"

/* FM_OK when v is finite and inside field's range; else FM_ERR_INVALID_ARGUMENT with
 * "<field>: V is outside [MIN, MAX] UNIT" (a parenthesis for an open end).  field must be in the table. */
fm_status param_check(fm_error *err, const char *field, double v);

/* "[-90, 90] degrees", "(0, 10]": the range as messages write it. */
void param_range_format(const fm_param_range *r, char *out, size_t size);

#endif

/* Reading JSON input files (custom atmospheres, aerosol biomes) with errors a user can act on: the
 * file and the line:column of a syntax error, or the JSON path ("$.layers[1].top_km") of a bad
 * value.  Every error is an invalid argument reported for the reader's field, as one line
 * "FIELD: FILE: PATH: what is wrong" (fm_fail_parameter), except running out of memory. */
#ifndef FM_BASE_JSON_FILE_H
#define FM_BASE_JSON_FILE_H

#include "base/status.h"

#include <cjson/cJSON.h>

/* Room for a JSON path such as $.constituents[11].phase.values[3][181]; longer ones are cut. */
#define JSON_PATH_CHARS 96

/* Where a problem is reported: the file as the user named it, the fm_error parameter it belongs to
 * ("atmosphere_file", "biome"), the caller's error. */
typedef struct json_reader {
    const char *file;
    const char *field;
    fm_error *err;
} json_reader;

/* Reads (at most 64 MiB) and parses rd->file.  On failure returns NULL with *status set: a missing
 * or unreadable file is an invalid argument ("FILE: cannot open: ..."), a syntax error is reported
 * as "FILE:LINE:COLUMN: JSON syntax error at '<text there>'".  Free the result with cJSON_Delete. */
cJSON *json_reader_load(const json_reader *rd, fm_status *status);

/* Fails with "FIELD: FILE: PATH: <formatted what>". */
fm_status json_bad(const json_reader *rd, const char *path, const char *fmt, ...) FM_PRINTF(3, 4);
fm_status json_out_of_memory(const json_reader *rd);

/* out[JSON_PATH_CHARS] = parent followed by the formatted suffix (".key", "[3]"). */
void json_child_path(char *out, const char *parent, const char *fmt, ...) FM_PRINTF(3, 4);

/* "a number", "an array", ... for messages. */
const char *json_type_name(const cJSON *node);

/* Fails on a key of obj that is not in `allowed` (NULL-terminated: typos are caught) or that is
 * repeated (cJSON would silently use the first). */
fm_status json_check_keys(const json_reader *rd, const cJSON *obj, const char *path, const char *const *allowed);
fm_status json_require_object(const json_reader *rd, const cJSON *node, const char *path);

/* A string member: absent gives *out = NULL when optional, an error when required. */
fm_status json_get_string(const json_reader *rd, const cJSON *obj, const char *path, const char *key, int required,
                          const char **out);

/* A required array member holding min to max elements, named `noun` in messages ("layers"). */
fm_status json_get_array(const json_reader *rd, const cJSON *obj, const char *path, const char *key, int min, int max,
                         const char *noun, const cJSON **out);

/* An interval of allowed values, printed as "[0, 1]", "(-1, 1)", "(0, 10000]". */
typedef struct json_interval {
    double lo, hi;
    int lo_open, hi_open;
} json_interval;

extern const json_interval json_any, json_positive, json_non_negative;

/* A finite number in r. */
fm_status json_get_number(const json_reader *rd, const cJSON *node, const char *path, json_interval r, double *out);
fm_status json_required_number(const json_reader *rd, const cJSON *obj, const char *path, const char *key,
                               json_interval r, double *out);
/* Absent: *out = fallback. */
fm_status json_optional_number(const json_reader *rd, const cJSON *obj, const char *path, const char *key,
                               json_interval r, double fallback, double *out);

/* An array of at least min_count numbers in r; *out is allocated (free it), NULL on failure. */
fm_status json_get_numbers(const json_reader *rd, const cJSON *node, const char *path, int min_count, json_interval r,
                           double **out, int *count);

/* x[] (read from path) strictly ascending; fails naming the first element that is not. */
fm_status json_check_ascending(const json_reader *rd, const char *path, const double *x, int n);

#endif

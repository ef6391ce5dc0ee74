/* Reading JSON input files (biomes, atmospheres) with errors a user can act on: the file name, the
 * line and column of a syntax error, or the JSON path ("$.layers[1].top_km") of a bad value. */
#ifndef FM_BASE_JSON_FILE_H
#define FM_BASE_JSON_FILE_H

#include "firmament/firmament.h"

#include <cjson/cJSON.h>

/* Parses the file; on failure fills err ("FILE: line L, column C: syntax error") and returns NULL.
 * Files over 16 MiB are refused (an input file that large is a mistake). */
cJSON *json_file_read(const char *path, fm_error *err);

/* A JSON path under construction while walking a document: "$", "$.layers", "$.layers[2]". */
typedef struct json_path {
    char text[192];
} json_path;

json_path json_path_root(void);
json_path json_path_key(const json_path *parent, const char *key);
json_path json_path_index(const json_path *parent, int index);

/* Fails with FM_ERR_INVALID_ARGUMENT and "FILE: PATH: <message>". */
fm_status json_fail(fm_error *err, const char *file, const json_path *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Every key of object must be in the NULL-terminated list (catches typos); fails naming the key. */
fm_status json_only_keys(const cJSON *object, const char *const *allowed, const char *file, const json_path *path,
                         fm_error *err);

/* A number member in [lo, hi]; missing: *out = fallback if optional, else an error. */
fm_status json_number(const cJSON *object, const char *key, double lo, double hi, int optional, double fallback,
                      double *out, const char *file, const json_path *path, fm_error *err);

#endif

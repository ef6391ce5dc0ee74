#include "base/json_file.h"

#include "base/status.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define JSON_FILE_MAX_BYTES (16L << 20)

static char *read_all(const char *path, long *size, fm_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        /* an input file the user named: bad input, not a runtime failure */
        fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cannot read '%s': %s", path, strerror(errno));
        return NULL;
    }
    char *text = NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) {
        if (n > JSON_FILE_MAX_BYTES) {
            fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s: %ld bytes is too large for a JSON input file", path, n);
        } else if (!(text = malloc((size_t)n + 1))) {
            fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory reading '%s'", path);
        } else if (fread(text, 1, (size_t)n, f) != (size_t)n) {
            fm_fail(err, FM_ERR_IO, "cannot read '%s'", path);
            free(text);
            text = NULL;
        } else {
            text[n] = '\0';
            *size = n;
        }
    } else {
        fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cannot read '%s': not a regular file", path);
    }
    fclose(f);
    return text;
}

cJSON *json_file_read(const char *path, fm_error *err)
{
    long size = 0;
    char *text = read_all(path, &size, err);
    if (!text)
        return NULL;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, (size_t)size + 1, &end, 1); /* + the terminator */
    if (!root) {
        /* cJSON reports where it stopped; turn that offset into a line and column */
        const char *at = end ? end : cJSON_GetErrorPtr();
        if (!at || at < text || at > text + size)
            at = text + size;
        int line = 1, column = 1;
        for (const char *c = text; c < at; c++) {
            if (*c == '\n') {
                line++;
                column = 1;
            } else {
                column++;
            }
        }
        fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s: line %d, column %d: JSON syntax error", path, line, column);
    }
    free(text);
    return root;
}

json_path json_path_root(void)
{
    json_path p;
    snprintf(p.text, sizeof p.text, "$");
    return p;
}

json_path json_path_key(const json_path *parent, const char *key)
{
    json_path p;
    snprintf(p.text, sizeof p.text, "%.120s.%.60s", parent->text, key);
    return p;
}

json_path json_path_index(const json_path *parent, int index)
{
    json_path p;
    snprintf(p.text, sizeof p.text, "%.170s[%d]", parent->text, index);
    return p;
}

fm_status json_fail(fm_error *err, const char *file, const json_path *path, const char *fmt, ...)
{
    char message[320];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s: %s: %s", file, path->text, message);
}

fm_status json_only_keys(const cJSON *object, const char *const *allowed, const char *file, const json_path *path,
                         fm_error *err)
{
    const cJSON *item;
    cJSON_ArrayForEach(item, object)
    {
        int known = 0;
        for (int i = 0; allowed[i] && !known; i++)
            known = item->string && strcmp(item->string, allowed[i]) == 0;
        if (!known) {
            json_path p = json_path_key(path, item->string ? item->string : "?");
            return json_fail(err, file, &p, "unknown key");
        }
    }
    return FM_OK;
}

fm_status json_number(const cJSON *object, const char *key, double lo, double hi, int optional, double fallback,
                      double *out, const char *file, const json_path *path, fm_error *err)
{
    json_path p = json_path_key(path, key);
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!item) {
        if (optional) {
            *out = fallback;
            return FM_OK;
        }
        return json_fail(err, file, &p, "missing (a number in [%g, %g])", lo, hi);
    }
    if (!cJSON_IsNumber(item))
        return json_fail(err, file, &p, "must be a number");
    double v = item->valuedouble;
    if (!isfinite(v) || v < lo || v > hi)
        return json_fail(err, file, &p, "%g is outside [%g, %g]", v, lo, hi);
    *out = v;
    return FM_OK;
}

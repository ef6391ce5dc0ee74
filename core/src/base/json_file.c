#include "base/json_file.h"

#include "base/platform.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_FILE_BYTES (64L << 20) /* far beyond any sensible input file; refuses a wrong file early */

const json_interval json_any = {-INFINITY, INFINITY, 1, 1};
const json_interval json_positive = {0.0, INFINITY, 1, 1};
const json_interval json_non_negative = {0.0, INFINITY, 0, 1};

fm_status json_bad(const json_reader *rd, const char *path, const char *fmt, ...)
{
    char what[384];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return fm_fail_parameter(rd->err, rd->field, "%s: %s: %s", rd->file, path, what);
}

fm_status json_out_of_memory(const json_reader *rd)
{
    return fm_fail(rd->err, FM_ERR_OUT_OF_MEMORY, "out of memory while reading %s", rd->file);
}

void json_child_path(char *out, const char *parent, const char *fmt, ...)
{
    size_t n = strlen(parent);
    if (n >= JSON_PATH_CHARS)
        n = JSON_PATH_CHARS - 1;
    memcpy(out, parent, n);
    out[n] = '\0';
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(out + n, JSON_PATH_CHARS - n, fmt, ap);
    va_end(ap);
}

const char *json_type_name(const cJSON *node)
{
    if (cJSON_IsNumber(node))
        return "a number";
    if (cJSON_IsString(node))
        return "a string";
    if (cJSON_IsArray(node))
        return "an array";
    if (cJSON_IsObject(node))
        return "an object";
    if (cJSON_IsBool(node))
        return "a boolean";
    return "null";
}

/* ---- reading and parsing ---------------------------------------------------------------------- */

static fm_status read_text(const json_reader *rd, char **out, size_t *size)
{
    *out = NULL;
    /* a FIFO or device would block the open or never end */
    struct stat info;
    if (stat(rd->file, &info) == 0 && !S_ISREG(info.st_mode))
        return fm_fail_parameter(rd->err, rd->field, "%s: not a regular file", rd->file);
    FILE *f = platform_fopen(rd->file, "rb");
    if (!f) /* a file the user named: bad input, not a runtime failure */
        return fm_fail_parameter(rd->err, rd->field, "%s: cannot open: %s", rd->file, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    fm_status st = FM_OK;
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap)
            break;
        if ((long)cap >= MAX_FILE_BYTES && fgetc(f) != EOF) { /* a file of exactly the limit is read */
            st = fm_fail_parameter(rd->err, rd->field, "%s: larger than %ld MiB: not an input file", rd->file,
                                   MAX_FILE_BYTES >> 20);
            break;
        }
        cap *= 2;
        char *grown = realloc(buf, cap + 1);
        if (!grown)
            free(buf);
        buf = grown;
    }
    if (!buf)
        st = json_out_of_memory(rd);
    else if (!st && ferror(f)) /* e.g. a directory */
        st = fm_fail_parameter(rd->err, rd->field, "%s: cannot read: %s", rd->file, strerror(errno));
    fclose(f);
    if (st) {
        free(buf);
        return st;
    }
    buf[n] = '\0';
    *out = buf;
    *size = n;
    return FM_OK;
}

/* The 1-based line and column of byte `offset` of text. */
static void line_column(const char *text, size_t offset, int *line, int *column)
{
    *line = *column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n')
            ++*line, *column = 1;
        else
            ++*column;
    }
}

static fm_status syntax_error(const json_reader *rd, const char *text, size_t size, const char *at)
{
    size_t offset = at && at >= text && at <= text + size ? (size_t)(at - text) : size;
    /* cJSON sometimes points just past the offending character (e.g. after a stray comma): on
     * whitespace, report the last character before it */
    while (offset < size && offset > 0 && isspace((unsigned char)text[offset]))
        offset--;
    int line, column;
    line_column(text, offset, &line, &column);
    if (offset >= size)
        return fm_fail_parameter(rd->err, rd->field, "%s:%d:%d: JSON syntax error: unexpected end of file", rd->file,
                                 line, column);
    int shown = 0; /* up to 12 characters of the line from there */
    while (shown < 12 && offset + shown < size && text[offset + shown] != '\n' && text[offset + shown] != '\r')
        shown++;
    return fm_fail_parameter(rd->err, rd->field, "%s:%d:%d: JSON syntax error at '%.*s'", rd->file, line, column, shown,
                             text + offset);
}

/* The length of the UTF-8 sequence at s (RFC 3629: no overlong forms, surrogates or code points above
 * U+10FFFF), or 0 where it is invalid */
static size_t utf8_length(const unsigned char *s, size_t left)
{
    if (s[0] < 0x80)
        return 1;
    size_t n = s[0] >= 0xc2 && s[0] <= 0xdf ? 2 : s[0] >= 0xe0 && s[0] <= 0xef ? 3 : s[0] >= 0xf0 && s[0] <= 0xf4 ? 4 : 0;
    if (n == 0 || n > left)
        return 0;
    for (size_t i = 1; i < n; i++)
        if ((s[i] & 0xc0) != 0x80)
            return 0;
    if ((s[0] == 0xe0 && s[1] < 0xa0) || (s[0] == 0xed && s[1] >= 0xa0) || (s[0] == 0xf0 && s[1] < 0x90) ||
        (s[0] == 0xf4 && s[1] >= 0x90))
        return 0;
    return n;
}

static fm_status lexical_error(const json_reader *rd, const char *text, size_t offset, const char *what)
{
    int line, column;
    line_column(text, offset, &line, &column);
    return fm_fail_parameter(rd->err, rd->field, "%s:%d:%d: JSON syntax error at byte %zu: %s", rd->file, line, column,
                             offset, what);
}

/* What cJSON accepts but RFC 8259 does not: raw control bytes (a NUL ended the value early), invalid
 * UTF-8, numbers with leading zeros, and a comma before a closing bracket (which cJSON reported at
 * the wrong place). Valid JSON passes unchanged; cJSON then finds the rest. */
static fm_status check_strict(const json_reader *rd, const char *text, size_t size)
{
    const unsigned char *t = (const unsigned char *)text;
    char what[96];
    int in_string = 0;
    for (size_t i = 0; i < size;) {
        size_t n = utf8_length(t + i, size - i);
        if (n == 0) {
            snprintf(what, sizeof what, "invalid UTF-8 (byte 0x%02x)", t[i]);
            return lexical_error(rd, text, i, what);
        }
        if (t[i] < 0x20 && (in_string || (t[i] != '\t' && t[i] != '\n' && t[i] != '\r'))) {
            snprintf(what, sizeof what, "raw control byte 0x%02x%s", t[i], in_string ? " in a string (escape it)" : "");
            return lexical_error(rd, text, i, what);
        }
        if (in_string) {
            if (t[i] == '"')
                in_string = 0;
            else if (t[i] == '\\' && i + 1 < size && t[i + 1] >= 0x20 && t[i + 1] < 0x80)
                i++; /* the escaped character */
        } else if (t[i] == '"') {
            in_string = 1;
        } else if (t[i] == '-' || isdigit(t[i])) {
            size_t d = i + (t[i] == '-');
            if (d + 1 < size && t[d] == '0' && isdigit(t[d + 1]))
                return lexical_error(rd, text, d, "a number with a leading zero");
            while (i + 1 < size && (isalnum(t[i + 1]) || t[i + 1] == '.' || t[i + 1] == '+' || t[i + 1] == '-'))
                i++;
        } else if (t[i] == ',') {
            size_t next = i + 1;
            while (next < size && isspace(t[next]))
                next++;
            if (next < size && (t[next] == '}' || t[next] == ']')) {
                snprintf(what, sizeof what, "a comma before '%c'", t[next]);
                return lexical_error(rd, text, i, what);
            }
        }
        i += n;
    }
    return FM_OK;
}

cJSON *json_reader_load(const json_reader *rd, fm_status *status)
{
    char *text = NULL;
    size_t size = 0;
    if ((*status = read_text(rd, &text, &size)))
        return NULL;
    if ((*status = check_strict(rd, text, size))) {
        free(text);
        return NULL;
    }
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, size + 1, &end, 1) /* with the NUL */;
    if (!root)
        *status = syntax_error(rd, text, size, end);
    free(text);
    return root;
}

/* ---- keys, strings, arrays -------------------------------------------------------------------- */

fm_status json_check_keys(const json_reader *rd, const cJSON *obj, const char *path, const char *const *allowed)
{
    for (const cJSON *it = obj->child; it; it = it->next) {
        int known = 0;
        for (const char *const *a = allowed; *a && !known; a++)
            known = strcmp(*a, it->string) == 0;
        if (!known) {
            char list[256] = "";
            for (const char *const *a = allowed; *a; a++) {
                size_t used = strlen(list);
                snprintf(list + used, sizeof list - used, "%s%s", a == allowed ? "" : ", ", *a);
            }
            return json_bad(rd, path, "unknown key \"%s\" (expected %s)", it->string, list);
        }
        for (const cJSON *prev = obj->child; prev != it; prev = prev->next)
            if (strcmp(prev->string, it->string) == 0)
                return json_bad(rd, path, "key \"%s\" appears twice", it->string);
    }
    return FM_OK;
}

fm_status json_require_object(const json_reader *rd, const cJSON *node, const char *path)
{
    if (!cJSON_IsObject(node))
        return json_bad(rd, path, "must be an object, not %s", json_type_name(node));
    return FM_OK;
}

fm_status json_get_string(const json_reader *rd, const cJSON *obj, const char *path, const char *key, int required,
                          const char **out)
{
    *out = NULL;
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!n)
        return required ? json_bad(rd, path, "missing \"%s\"", key) : FM_OK;
    if (!cJSON_IsString(n)) {
        char p[JSON_PATH_CHARS];
        json_child_path(p, path, ".%s", key);
        return json_bad(rd, p, "must be a string, not %s", json_type_name(n));
    }
    *out = n->valuestring;
    return FM_OK;
}

fm_status json_get_array(const json_reader *rd, const cJSON *obj, const char *path, const char *key, int min, int max,
                         const char *noun, const cJSON **out)
{
    *out = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!*out)
        return json_bad(rd, path, "missing \"%s\"", key);
    char p[JSON_PATH_CHARS];
    json_child_path(p, path, ".%s", key);
    if (!cJSON_IsArray(*out))
        return json_bad(rd, p, "must be an array, not %s", json_type_name(*out));
    int count = cJSON_GetArraySize(*out);
    if (count < min || count > max)
        return json_bad(rd, p, "must hold %d to %d %s, holds %d", min, max, noun, count);
    return FM_OK;
}

/* ---- numbers ---------------------------------------------------------------------------------- */

static int in_interval(double v, json_interval r)
{
    return (r.lo_open ? v > r.lo : v >= r.lo) && (r.hi_open ? v < r.hi : v <= r.hi);
}

static fm_status check_value(const json_reader *rd, const char *path, double v, json_interval r)
{
    if (in_interval(v, r))
        return FM_OK;
    if (r.lo == 0.0 && isinf(r.hi))
        return json_bad(rd, path, "must be %s, not %g", r.lo_open ? "positive" : "non-negative", v);
    return json_bad(rd, path, "must be in %c%g, %g%c, not %.10g", r.lo_open ? '(' : '[', r.lo, r.hi, r.hi_open ? ')' : ']',
                    v);
}

fm_status json_get_number(const json_reader *rd, const cJSON *node, const char *path, json_interval r, double *out)
{
    if (!cJSON_IsNumber(node))
        return json_bad(rd, path, "must be a number, not %s", json_type_name(node));
    if (!isfinite(node->valuedouble))
        return json_bad(rd, path, "must be a finite number");
    *out = node->valuedouble;
    return check_value(rd, path, *out, r);
}

fm_status json_required_number(const json_reader *rd, const cJSON *obj, const char *path, const char *key,
                               json_interval r, double *out)
{
    if (!cJSON_GetObjectItemCaseSensitive(obj, key))
        return json_bad(rd, path, "missing \"%s\"", key);
    return json_optional_number(rd, obj, path, key, r, 0.0, out);
}

fm_status json_optional_number(const json_reader *rd, const cJSON *obj, const char *path, const char *key,
                               json_interval r, double fallback, double *out)
{
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!n) {
        *out = fallback;
        return FM_OK;
    }
    char p[JSON_PATH_CHARS];
    json_child_path(p, path, ".%s", key);
    return json_get_number(rd, n, p, r, out);
}

fm_status json_get_numbers(const json_reader *rd, const cJSON *node, const char *path, int min_count, json_interval r,
                           double **out, int *count)
{
    *out = NULL;
    if (!cJSON_IsArray(node))
        return json_bad(rd, path, "must be an array of numbers, not %s", json_type_name(node));
    int n = cJSON_GetArraySize(node);
    if (n < min_count)
        return json_bad(rd, path, "needs at least %d value%s, has %d", min_count, min_count == 1 ? "" : "s", n);
    double *v = malloc(sizeof(double) * (size_t)n);
    if (!v)
        return json_out_of_memory(rd);
    int i = 0;
    for (const cJSON *it = node->child; it; it = it->next, i++) {
        char p[JSON_PATH_CHARS];
        json_child_path(p, path, "[%d]", i);
        fm_status s = json_get_number(rd, it, p, r, &v[i]);
        if (s) {
            free(v);
            return s;
        }
    }
    *out = v;
    *count = n;
    return FM_OK;
}

fm_status json_check_ascending(const json_reader *rd, const char *path, const double *x, int n)
{
    for (int i = 1; i < n; i++)
        if (!(x[i] > x[i - 1])) {
            char p[JSON_PATH_CHARS];
            json_child_path(p, path, "[%d]", i);
            return json_bad(rd, p, "must be greater than the value before it (%g), not %g", x[i - 1], x[i]);
        }
    return FM_OK;
}

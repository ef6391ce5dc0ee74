#include "base/sealed_file.h"

#include "base/hash.h"
#include "base/platform.h"
#include "base/stale_temps.h"
#include "base/status.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BYTE_ORDER_MARK 0x01020304u /* native integers and floats: another machine's order is refused */

typedef struct header {
    char magic[8];
    uint32_t version, byte_order;
    char key[32];
    uint64_t bytes, checksum;
} header;

#define HEADER_BYTES (8 + 4 + 4 + 32 + 8 + 8)

static unsigned char *put(unsigned char *out, const void *v, size_t n)
{
    memcpy(out, v, n);
    return out + n;
}

static const unsigned char *get(const unsigned char *in, void *v, size_t n)
{
    memcpy(v, in, n);
    return in + n;
}

static void header_pack(const header *h, unsigned char *out)
{
    out = put(out, h->magic, 8);
    out = put(out, &h->version, 4);
    out = put(out, &h->byte_order, 4);
    out = put(out, h->key, 32);
    out = put(out, &h->bytes, 8);
    put(out, &h->checksum, 8);
}

static void header_unpack(const unsigned char *in, header *h)
{
    in = get(in, h->magic, 8);
    in = get(in, &h->version, 4);
    in = get(in, &h->byte_order, 4);
    in = get(in, h->key, 32);
    in = get(in, &h->bytes, 8);
    get(in, &h->checksum, 8);
}

static fm_status write_all(const char *tmp, const unsigned char *head, const void *body, size_t n)
{
    FILE *f = platform_fopen(tmp, "wb");
    if (!f)
        return FM_ERR_IO;
    int ok = fwrite(head, 1, HEADER_BYTES, f) == HEADER_BYTES && (n == 0 || fwrite(body, 1, n, f) == n);
    ok = fclose(f) == 0 && ok;
    return ok ? FM_OK : FM_ERR_IO;
}

/* A temporary that a killed writer left is removed by the next write of a file of its kind once it
 * is this old (s): writing a cache file takes seconds. */
#define STALE_TEMP_S 3600.0

/* Removes the stale temporaries of files named as path but for its key, if its name holds it. */
static void remove_stale_temps(const char *tmp, const char key[32])
{
    const char *slash = platform_last_separator(tmp), *name = slash ? slash + 1 : tmp;
    char k[33];
    memcpy(k, key, 32);
    k[32] = '\0';
    const char *at = strstr(name, k);
    size_t from = at ? (size_t)(at - name) : 0;
    stale_temps_remove(tmp, from, at ? from + 32 : from, STALE_TEMP_S);
}

fm_status sealed_file_write(const char *path, const sealed_format *format, const char key[32], const void *payload,
                            size_t bytes, fm_error *err)
{
    if (!path || !path[0])
        return fm_fail(err, FM_ERR_IO, "cannot write the %s: no path", format->what);
    char *tmp = malloc(strlen(path) + 8);
    if (!tmp)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    header h = {.version = format->version, .byte_order = BYTE_ORDER_MARK, .bytes = bytes,
                .checksum = hash_bytes(payload, bytes, format->checksum_seed)};
    memcpy(h.magic, format->magic, 8);
    memcpy(h.key, key, 32);
    unsigned char head[HEADER_BYTES];
    header_pack(&h, head);
    fm_status s = FM_OK;
    sprintf(tmp, "%s.XXXXXX", path);
    if (platform_create_unique(tmp) != 0)
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    else if (write_all(tmp, head, payload, bytes) || platform_rename_replace(tmp, path) != 0) {
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
        platform_remove(tmp);
    } else
        remove_stale_temps(tmp, key);
    free(tmp);
    return s;
}

/* The whole file, or NULL (err filled). */
static unsigned char *read_all(const char *path, size_t *n, fm_error *err)
{
    FILE *f = platform_fopen(path, "rb");
    if (!f) {
        fm_fail(err, FM_ERR_IO, "cannot read '%s': %s", path, strerror(errno));
        return NULL;
    }
    size_t cap = 1 << 16, len = 0;
    unsigned char *buf = malloc(cap);
    while (buf) {
        len += fread(buf + len, 1, cap - len, f);
        if (len < cap)
            break;
        unsigned char *more = realloc(buf, cap *= 2);
        if (!more)
            free(buf);
        buf = more;
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf)
        fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory reading '%s'", path);
    else if (bad) {
        fm_fail(err, FM_ERR_IO, "cannot read '%s'", path);
        free(buf);
        buf = NULL;
    }
    *n = len;
    return buf;
}

/* Why the file cannot be used (after "not a ... file", checked first), or NULL when it can. */
static const char *refusal(const sealed_format *format, const header *h, size_t file_bytes, const char *key,
                           const unsigned char *body)
{
    if (h->version != format->version || h->byte_order != BYTE_ORDER_MARK)
        return "written by another version or machine";
    if (memcmp(h->key, key, 32) != 0)
        return format->other_key;
    if (h->bytes != file_bytes - HEADER_BYTES)
        return "truncated or extended";
    if (hash_bytes(body, (size_t)h->bytes, format->checksum_seed) != h->checksum)
        return "corrupt (checksum)";
    return NULL;
}

fm_status sealed_file_read(const char *path, const sealed_format *format, const char key[32], unsigned char **payload,
                           size_t *bytes, fm_error *err)
{
    *payload = NULL;
    *bytes = 0;
    size_t n;
    unsigned char *file = read_all(path, &n, err);
    if (!file)
        return err ? err->status : FM_ERR_IO;
    header h = {0};
    if (n >= HEADER_BYTES)
        header_unpack(file, &h);
    fm_status s = FM_OK;
    const char *why;
    if (n < HEADER_BYTES || memcmp(h.magic, format->magic, 8) != 0)
        s = fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s '%s': not a %s file", format->what, path, format->what);
    else if ((why = refusal(format, &h, n, key, file + HEADER_BYTES)))
        s = fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s '%s': %s", format->what, path, why);
    if (s) {
        free(file);
        return s;
    }
    memmove(file, file + HEADER_BYTES, n - HEADER_BYTES);
    *payload = file;
    *bytes = n - HEADER_BYTES;
    return FM_OK;
}

int sealed_file_make_dirs(const char *dir)
{
    size_t n = strlen(dir);
    char *d = malloc(n + 1);
    if (!d)
        return -1;
    memcpy(d, dir, n + 1);
    int failed = 0;
    for (char *c = d + 1; *c && !failed; c++) {
        if (*c != '/' && *c != '\\')
            continue;
        char sep = *c;
        *c = '\0';
        failed = platform_path_kind(d) != PLATFORM_DIRECTORY && platform_make_dir(d) != 0;
        *c = sep;
    }
    failed = failed || platform_make_dir(d) != 0;
    free(d);
    return failed ? -1 : 0;
}

int fm_default_cache_dir(char *out, size_t size)
{
#ifdef _WIN32
    const char *base = getenv("LOCALAPPDATA"), *below = "";
#else
    const char *base = getenv("XDG_CACHE_HOME"), *below = "";
    if (!base || !base[0]) { /* the XDG base directory default */
        base = getenv("HOME");
        below = "/.cache";
    }
#endif
    if (!base || !base[0])
        return -1;
    snprintf(out, size, "%s%s/firmament", base, below);
    return 0;
}

/* The live sky's file: a header (magic, version, byte order, the atmosphere's key, the tables' size
 * and checksum) and the tables (live.c).  Written to a temporary file beside the path and renamed;
 * read whole and checked before anything in it is used. */
#include "base/hash.h"
#include "base/platform.h"
#include "base/status.h"
#include "render/live.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char MAGIC[8] = {'F', 'M', 'L', 'I', 'V', 'E', '\r', '\n'};
#define FILE_VERSION 1u
#define BYTE_ORDER_MARK 0x01020304u
#define CHECKSUM_SEED 0x6c697665ull /* "live" */

typedef struct live_header {
    char magic[8];
    uint32_t version, byte_order;
    char key[32];
    uint64_t bytes, checksum;
} live_header;

#define HEADER_BYTES (8 + 4 + 4 + 32 + 8 + 8)

static void header_pack(const live_header *h, unsigned char *out)
{
    memcpy(out, h->magic, 8);
    memcpy(out + 8, &h->version, 4);
    memcpy(out + 12, &h->byte_order, 4);
    memcpy(out + 16, h->key, 32);
    memcpy(out + 48, &h->bytes, 8);
    memcpy(out + 56, &h->checksum, 8);
}

static void header_unpack(const unsigned char *in, live_header *h)
{
    memcpy(h->magic, in, 8);
    memcpy(&h->version, in + 8, 4);
    memcpy(&h->byte_order, in + 12, 4);
    memcpy(h->key, in + 16, 32);
    memcpy(&h->bytes, in + 48, 8);
    memcpy(&h->checksum, in + 56, 8);
}

static fm_status write_all(const char *tmp, const unsigned char *head, const unsigned char *body, size_t n)
{
    FILE *f = platform_fopen(tmp, "wb");
    if (!f)
        return FM_ERR_IO;
    int ok = fwrite(head, 1, HEADER_BYTES, f) == HEADER_BYTES && (n == 0 || fwrite(body, 1, n, f) == n);
    ok = fclose(f) == 0 && ok;
    return ok ? FM_OK : FM_ERR_IO;
}

fm_status fm_sky_live_save(const fm_sky_live *live, const char *path, fm_error *err)
{
    if (!path || !path[0])
        return fm_fail(err, FM_ERR_IO, "cannot write the live sky: no path");
    size_t n = live_payload_size(live);
    unsigned char *body = malloc(n ? n : 1);
    char *tmp = malloc(strlen(path) + 8);
    if (!body || !tmp) {
        free(body);
        free(tmp);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    }
    live_payload_write(live, body);
    live_header h = {.version = FILE_VERSION, .byte_order = BYTE_ORDER_MARK, .bytes = n,
                     .checksum = hash_bytes(body, n, CHECKSUM_SEED)};
    memcpy(h.magic, MAGIC, 8);
    char key[33];
    fm_sky_live_key(&live->params, key);
    memcpy(h.key, key, 32);
    unsigned char head[HEADER_BYTES];
    header_pack(&h, head);
    fm_status s = FM_OK;
    sprintf(tmp, "%s.XXXXXX", path);
    if (platform_create_unique(tmp) != 0)
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    else if (write_all(tmp, head, body, n) || platform_rename_replace(tmp, path) != 0) {
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
        platform_remove(tmp);
    }
    free(body);
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

/* Why the file cannot be this atmosphere's live sky, or NULL when it can. */
static const char *refusal(const live_header *h, size_t file_bytes, const char *key, const unsigned char *body)
{
    if (file_bytes < HEADER_BYTES || memcmp(h->magic, MAGIC, 8) != 0)
        return "not a live sky file";
    if (h->version != FILE_VERSION || h->byte_order != BYTE_ORDER_MARK)
        return "written by another version or machine";
    if (memcmp(h->key, key, 32) != 0)
        return "the tables of another atmosphere";
    if (h->bytes != file_bytes - HEADER_BYTES)
        return "truncated or extended";
    if (hash_bytes(body, (size_t)h->bytes, CHECKSUM_SEED) != h->checksum)
        return "corrupt (checksum)";
    return NULL;
}

fm_status fm_sky_live_load(const fm_sky_params *params, const char *path, fm_sky_live **out, fm_error *err)
{
    *out = NULL;
    size_t n;
    unsigned char *file = read_all(path, &n, err);
    if (!file)
        return err ? err->status : FM_ERR_IO;
    live_header h = {0};
    if (n >= HEADER_BYTES)
        header_unpack(file, &h);
    char key[33];
    fm_sky_params resolved;
    fm_status s = live_sky_params(params, &resolved, err);
    if (!s) {
        fm_sky_live_key(params, key);
        const char *why = refusal(&h, n, key, file + HEADER_BYTES);
        s = why ? fm_fail(err, FM_ERR_INVALID_ARGUMENT, "live sky '%s': %s", path, why)
                : live_from_payload(&resolved, file + HEADER_BYTES, n - HEADER_BYTES, out, err);
    }
    free(file);
    return s;
}

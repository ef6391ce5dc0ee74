/* libFuzzer targets read user files by path: each input is written to one temporary file per
 * process (under $TMPDIR), rewritten for every input. */
#ifndef FM_FUZZ_FILE_H
#define FM_FUZZ_FILE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

/* The temporary file's path, holding data; NULL when it could not be written. */
static const char *fuzz_file(const uint8_t *data, size_t size, const char *suffix)
{
    static char path[256];
    if (!path[0]) {
        const char *dir = getenv("TMPDIR");
        snprintf(path, sizeof path, "%s/fm_fuzz_%ld%s", dir && dir[0] ? dir : "/tmp", (long)getpid(), suffix);
    }
    FILE *f = fopen(path, "wb");
    if (!f)
        return NULL;
    size_t written = fwrite(data, 1, size, f);
    if (fclose(f) != 0 || written != size)
        return NULL;
    return path;
}

#endif

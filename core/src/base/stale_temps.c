#define _POSIX_C_SOURCE 200809L /* PATH_MAX */
#include "base/stale_temps.h"

#include "base/platform.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

typedef struct stale_scan {
    const char *dir; /* "<dir>/" or "" */
    int dir_len;
    const char *name; /* the new temporary's */
    size_t length, any_from, any_to;
    double max_age_s;
} stale_scan;

static int matches(const stale_scan *scan, const char *name)
{
    if (strlen(name) != scan->length)
        return 0;
    for (size_t i = 0; i < scan->length; i++) {
        unsigned char c = (unsigned char)name[i];
        if (i + 6 >= scan->length ? !isalnum(c)
            : i >= scan->any_from && i < scan->any_to ? !(isdigit(c) || (c >= 'a' && c <= 'f'))
                                                      : c != (unsigned char)scan->name[i])
            return 0;
    }
    return 1;
}

static void remove_if_stale(void *ctx, const char *name)
{
    const stale_scan *scan = ctx;
    if (!matches(scan, name))
        return;
    char full[PLATFORM_PATH_MAX + 16];
    snprintf(full, sizeof full, "%.*s%s", scan->dir_len, scan->dir, name);
    if (platform_path_kind(full) == PLATFORM_FILE && platform_file_age_s(full) > scan->max_age_s)
        platform_remove(full);
}

void stale_temps_remove(const char *tmp, size_t any_from, size_t any_to, double max_age_s)
{
    const char *slash = platform_last_separator(tmp);
    int dir_len = slash ? (int)(slash - tmp + 1) : 0;
    stale_scan scan = {tmp, dir_len, tmp + dir_len, strlen(tmp + dir_len), any_from, any_to, max_age_s};
    if (scan.length < 6)
        return;
    char dir[PLATFORM_PATH_MAX + 16];
    snprintf(dir, sizeof dir, "%.*s", dir_len ? dir_len : 1, dir_len ? tmp : ".");
    platform_list_dir(dir, remove_if_stale, &scan);
}

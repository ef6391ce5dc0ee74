#include "presets.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int is_directory(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

const char *presets_dir(const char *given)
{
    if (given && given[0])
        return given;
    const char *env = getenv("FIRMAMENT_PRESETS");
    if (env && env[0])
        return env;
    return is_directory(FIRMAMENT_SOURCE_PRESETS) ? FIRMAMENT_SOURCE_PRESETS : FIRMAMENT_INSTALLED_PRESETS;
}

void presets_list(const char *dir, const char *what, char *out, size_t size)
{
    char names[48][64];
    int count = 0;
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL && count < 48) {
        size_t n = strlen(e->d_name);
        if (n > 5 && n < 64 && strcmp(e->d_name + n - 5, ".json") == 0) {
            snprintf(names[count], sizeof names[count], "%.*s", (int)(n - 5), e->d_name);
            count++;
        }
    }
    if (d)
        closedir(d);
    for (int i = 1; i < count; i++) /* insertion sort: a handful of names */
        for (int j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; j--) {
            char t[64];
            memcpy(t, names[j], sizeof t);
            memcpy(names[j], names[j - 1], sizeof t);
            memcpy(names[j - 1], t, sizeof t);
        }
    out[0] = '\0';
    size_t used = 0;
    for (int i = 0; i < count && used < size; i++)
        used += (size_t)snprintf(out + used, size - used, "%s%s", i ? ", " : "", names[i]);
    if (count == 0)
        snprintf(out, size, "no %s files found in %.400s", what, dir);
}
